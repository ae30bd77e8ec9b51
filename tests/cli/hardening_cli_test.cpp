// bad or extreme command-line values: each is an input error (exit 3) naming the option and
// its value, before any work, with nothing left in the output folder.
#include <catch2/catch.hpp>

#include "cli_support.hpp"

using namespace camopt::test;

TEST_CASE("a value that is not a finite number is an input error naming the option", "[cli][hardening]") {
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  const std::string target = (source_dir() / "designs/targets/rff_intake_lift.csv").string();
  struct Case {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"kinematics", rff, "--step", "nan"}, "--step: value 'nan' is not a finite number"},
      {{"kinematics", rff, "--rpm", "-1e999"}, "--rpm: value '-1e999' is not a finite number"},
      {{"kinematics", rff, "--control", "nan"}, "--control: value 'nan' is not a finite number"},
      {{"dynamics", rff, "--model", "rigid", "--rpm", "1000,inf"}, "--rpm: value 'inf' is not a finite number"},
      {{"dynamics", rff, "--model", "rigid", "--rpm", "1000:NaN:3"}, "--rpm: value 'NaN' is not a finite number"},
      {{"synthesize", target, "--design", rff, "--wheel-radius=nan"}, "--wheel-radius: value 'nan' is not a finite number"},
      {{"synthesize", target, "--design", rff, "--master-radius", "inf"}, "--master-radius: value 'inf' is not a finite"},
      {{"lift", "--law", "polynomial-4567", "--lift", "infinity"}, "--lift: value 'infinity' is not a finite number"},
  };
  for (const auto& c : cases) {
    TempDir tmp;
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--out", (tmp / "out").string()});
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(r.err.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(tmp / "out"));
  }
}

TEST_CASE("an input that is not a readable regular file of bounded size is an input error saying why",
          "[cli][hardening]") {
  TempDir tmp;
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  struct Case {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"validate", "/dev/zero"}, "/dev/zero: cannot read design file: is not a regular file"},
      {{"validate", tmp.path().string()}, "cannot read design file: is a directory"},
      {{"validate", (tmp / "missing.toml").string()}, "missing.toml: cannot read design file: no such file"},
      {{"synthesize", "/dev/zero", "--design", rff, "--out", (tmp / "out").string()},
       "/dev/zero: cannot read csv file: is not a regular file"},
  };
  for (const auto& c : cases) {
    const auto r = run_camopt(c.args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(r.err.find(c.expect) != std::string::npos);
  }
  CHECK_FALSE(fs::exists(tmp / "out"));
}

TEST_CASE("sweeps past the documented point limits are input errors before any allocation", "[cli][hardening]") {
  TempDir tmp;
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  const std::string cvvl = (source_dir() / "designs/cvvl_swing_cam.toml").string();
  struct Case {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"kinematics", rff, "--step", "1e-17"}, "--step: value 1e-17 gives 3.6e+19 points over the driver range 0..360 (at most 1e+06)"},
      {{"kinematics", cvvl, "--control", "0:16:100000"}, "--control: 100000 runs x 361 points = 3.61e+07 (at most 2e+07)"},
      {{"dynamics", rff, "--model", "rigid", "--rpm", "3000", "--step", "1e-6"}, "--step: value 1e-06 gives 3.6e+08 points"},
      {{"lift", "--law", "polynomial-4567", "--step", "1e-9"}, "--step = 1e-09 cam deg: gives 3.6e+11 rows per cycle"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--out", (tmp / "out").string()});
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(r.err.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(tmp / "out"));
  }
  // a design's own step: validate names the key and the bound
  std::string text = read_file(source_dir() / "designs/bucket_tappet.toml");
  text.replace(text.find("[driver]\n"), 9, "[driver]\nstep_deg = 1e-300\n");
  text.replace(text.find("file = \"profiles/"), 17, "file = \"" + (source_dir() / "designs/profiles/").string());
  write_text(tmp / "d.toml", text);
  const auto r = run_camopt({"validate", (tmp / "d.toml").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("driver.step_deg: value 1e-300 must be >= (stop_deg - start_deg) / 1e6") != std::string::npos);
}

TEST_CASE("messages: a value out of range is an input error in a few words, a typo'd subcommand is named",
          "[cli][hardening]") {
  TempDir tmp;
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  auto r = run_camopt({"kinematics", rff, "--step", "0", "--out", (tmp / "out").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("--step: value 0 must be > 0") != std::string::npos);
  CHECK(r.err.size() < 200);  // not the whole double range
  r = run_camopt({"synthesize", (source_dir() / "designs/targets/rff_intake_lift.csv").string(), "--design", rff,
                  "--wheel-radius", "-3", "--out", (tmp / "out").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("--wheel-radius: value -3 must be >= 0") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp / "out"));
  r = run_camopt({"kinematcs", rff});
  INFO(r.all());
  CHECK(r.exit_code == cli_usage_error);
  CHECK(r.err.find("unknown subcommand 'kinematcs' (subcommands: validate, kinematics,") != std::string::npos);
}

TEST_CASE("physical inputs past their documented ranges are input errors naming the key", "[cli][hardening]") {
  TempDir tmp;
  const std::string base = [] {
    std::string t = read_file(source_dir() / "designs/bucket_tappet.toml");
    t.replace(t.find("file = \"profiles/"), 17, "file = \"" + (source_dir() / "designs/profiles/").string());
    return t;
  }();
  struct Case {
    std::string from, to, expect;
  };
  const std::vector<Case> cases = {
      {"[driver]\n", "[driver]\ncrank_per_cam = 1e-300\n", "driver.crank_per_cam: value 1e-300 must be in [0.01, 100]"},
      {"mass_kg = 0.0573", "mass_kg = 1e308", "node[1].mass_kg: value 1e+308 must be in (0, 1000]"},
      {"youngs_modulus_GPa = 210", "youngs_modulus_GPa = 1e308", "youngs_modulus_GPa: value 1e+308 must be in [0.001, 2000]"},
      {"rate_N_per_mm = 40", "rate_N_per_mm = 1e300", "rate_N_per_mm: value 1e+300 must be in (0, 1e+07]"},
  };
  for (const auto& c : cases) {
    std::string text = base;
    text.replace(text.find(c.from), c.from.size(), c.to);
    write_text(tmp / "d.toml", text);
    const auto r = run_camopt({"validate", (tmp / "d.toml").string()});
    INFO(r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(r.err.find(c.expect) != std::string::npos);
  }
  const auto r = run_camopt({"dynamics", (source_dir() / "designs/bucket_tappet.toml").string(), "--model", "rigid",
                             "--rpm", "1e300", "--out", (tmp / "out").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("--rpm: value 1e+300 must be in (0, 1e6]") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp / "out"));
}

TEST_CASE("an option the chosen mode ignores is an input error, not a silent default", "[cli][hardening]") {
  TempDir tmp;
  const std::string rff = (source_dir() / "designs/roller_finger_follower.toml").string();
  struct Case {
    std::vector<std::string> args;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"dynamics", rff, "--model", "rigid", "--rpm", "3000", "--rtol", "1e-8"}, "--rtol: does nothing with --model rigid"},
      {{"dynamics", rff, "--model", "flexible", "--rpm", "3000", "--contacts", "compliant"},
       "--contacts: does nothing with --model flexible"},
      {{"dynamics", rff, "--model", "rigid", "--rpm", "3000", "--cam-deg", "180"}, "--cam-deg: does nothing with --model rigid"},
      {{"optimize", rff, "--constraints", (source_dir() / "constraints/passenger_car_intake.toml").string(), "--starts", "3"},
       "--starts: does nothing with --solver ipopt (global only)"},
      {{"synthesize", (source_dir() / "designs/targets/rff_intake_lift.csv").string(), "--design", rff, "--knot-spacing", "2"},
       "--knot-spacing: does nothing without --smooth"},
      {{"kinematics", rff, "--outputs", ""}, "--outputs: empty"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--out", (tmp / "out").string()});
    const auto r = run_camopt(args);
    INFO(r.command << "\n" << r.all());
    CHECK(r.exit_code == cli_input_error);
    CHECK(r.err.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(tmp / "out"));
  }
}

TEST_CASE("a target with two lift columns is an input error naming both", "[cli][hardening]") {
  TempDir tmp;
  write_text(tmp / "two.csv", "cam_deg,valve_lift_mm,lift_mm\n0,0,0\n1,0.1,0.2\n2,0.2,0.4\n");
  const auto r = run_camopt({"synthesize", (tmp / "two.csv").string(), "--design",
                             (source_dir() / "designs/roller_finger_follower.toml").string(), "--out", (tmp / "out").string()});
  INFO(r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("more than one value column ('valve_lift_mm', 'lift_mm')") != std::string::npos);
  CHECK_FALSE(fs::exists(tmp / "out"));
}

TEST_CASE("synthesize and optimize refuse to overwrite their own input", "[cli][hardening]") {
  TempDir tmp;
  const std::string target = (source_dir() / "designs/targets/rff_intake_lift.csv").string();
  auto r = run_camopt({"synthesize", target, "--design", (source_dir() / "designs/roller_finger_follower.toml").string(),
                       "--out", (tmp / "o").string()});
  REQUIRE(r.exit_code == cli_ok);
  const std::string before = read_file(tmp / "o/design.toml");
  r = run_camopt({"synthesize", target, "--design", (tmp / "o/design.toml").string(), "--out", (tmp / "o").string()});
  INFO(r.all());
  CHECK(r.exit_code == cli_input_error);
  CHECK(r.err.find("holds the input") != std::string::npos);
  CHECK(r.err.find("o/design.toml': the results would overwrite it") != std::string::npos);
  CHECK(read_file(tmp / "o/design.toml") == before);
  r = run_camopt({"optimize", (tmp / "o/design.toml").string(), "--constraints",
                  (source_dir() / "constraints/passenger_car_intake.toml").string(), "--out", (tmp / "o").string()});
  CHECK(r.exit_code == cli_input_error);
  CHECK(read_file(tmp / "o/design.toml") == before);
}
