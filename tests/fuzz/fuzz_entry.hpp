#pragma once
// the code the fuzzers drive (tests/fuzz/fuzz_*.cpp, libFuzzer) and the regression test
// replays (fuzz_regression_test.cpp): one reader per function, fed arbitrary bytes.
// Contract: an input is either accepted (true) or rejected with camopt::InputError (false);
// anything else
// (another exception, a crash, a NaN in an accepted result) is a bug and aborts with
// a message naming the target.
#include <string_view>

namespace camopt::fuzz {

// a target valve-lift table: io::parse_csv -> io::read_angle_table -> fit_target_lift,
// interpolated and smoothed (accepted when either is)
bool target_lift_csv(std::string_view bytes);
// a design file: io::parse_design -> kin::compile -> a 30 deg kinematic sweep with every output
bool design_toml(std::string_view bytes);
// a constraint set for `camopt optimize`: io::parse_constraints
bool constraint_toml(std::string_view bytes);

}  // namespace camopt::fuzz
