# ctest-time script (a TEST_INCLUDE_FILES entry, read after the discovered Catch2 tests): the
# tests labelled release_only run in the Release suite and are left out of the sanitizer stage
# (scripts/setup.sh --sanitize --test; docs/testing.md "CI"). Each is a long sweep or an
# external process whose C++ paths the rest of the suite also runs under the sanitizers:
# - the seat-penetration sweep: every bundled design at 9 speeds with the flexible model
#   (163 s under ASan); the flexible, seat and HLA code it runs is in the dynamics tests.
set_tests_properties(
  "dynamics:flexible: no bundled valve passes through its seat beyond the seat's elastic approach, 1000-9000 rpm"
  PROPERTIES LABELS release_only)
