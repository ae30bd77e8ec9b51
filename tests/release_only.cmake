# ctest-time script (a TEST_INCLUDE_FILES entry, read after the discovered Catch2 tests): the
# tests labelled release_only run in the Release suite and are left out of the sanitizer stage
# (scripts/setup.sh --sanitize --test; docs/testing.md "CI"). Each is a long sweep or an
# external process whose C++ paths the rest of the suite also runs under the sanitizers:
# - the seat-penetration sweep: every bundled design at 9 speeds with the flexible model
#   (163 s under ASan); the flexible, seat and HLA code it runs is in the dynamics tests;
# - the valve oracle against a fixed-step RK4: the test's own integrator over the oracle in
#   tests/oracles, no library code;
# - the CLI's long sweeps stopped by a signal, and two runs racing for one folder or a failing
#   re-run: each runs the CLI process several times over; the writing, locking and commit code
#   they go through runs in every other CLI test.
set_tests_properties(
  "dynamics:flexible: no bundled valve passes through its seat beyond the seat's elastic approach, 1000-9000 rpm"
  "oracles:valve oracle: agrees with a fixed-step RK4 of the non-smooth equation"
  "cli:a run stopped by SIGTERM or SIGINT while it writes leaves no temporary file"
  "cli:two runs into one folder at once each commit a whole set: the folder never holds a mix"
  "cli:a failing re-run leaves the previous set as it was, a different one replaces it whole"
  PROPERTIES LABELS release_only)
