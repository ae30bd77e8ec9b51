// --set KEY=VALUE on the subcommands that read a design: the run equals the run of a design
// file edited by hand, bit for bit; summary.json and report.json record the overrides; the
// design synthesize writes carries them; a bad override is exit 3 naming it
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "camopt/io/design_document.hpp"
#include "camopt/io/design_file.hpp"
#include "cli/cli_support.hpp"
#include "cli/command_test_support.hpp"

using namespace camopt::test;
using namespace camopt::test::commands;

namespace {

const std::string kEccentric = (source_dir() / "designs/eccentric_offset_roller.toml").string();

// `text` with its first `from` replaced by `to`
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// the eccentric design edited by hand: roller radius 9 and touch at rest
std::string eccentric_by_hand() {
  std::string text = read_file(kEccentric);
  text = replaced(text, "center_mm = [3, 23.8118], radius_mm = 8,", "center_mm = [3, 23.8118], radius_mm = 9,");
  return replaced(text, "width_mm = 10\n", "width_mm = 10\ntouch_at_rest = true\n");
}
const std::vector<std::string> kSets = {"--set", "connection.disc_roller.b.radius_mm=9", "--set",
                                        "connection.disc_roller.touch_at_rest=true"};

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

}  // namespace

TEST_CASE("kinematics with --set equals the run of the edited file", "[cli][set]") {
  TempDir tmp;
  const std::string edited = tmp.write("edited.toml", eccentric_by_hand());
  const auto a = run_camopt(with({"kinematics", kEccentric, "--out", tmp.file("a"), "--step", "2"}, kSets));
  const auto b = run_camopt({"kinematics", edited, "--out", tmp.file("b"), "--step", "2"});
  INFO(a.all() << b.all());
  REQUIRE(a.exit_code == cli_ok);
  REQUIRE(b.exit_code == cli_ok);
  CHECK(read_file(tmp / "a/kinematics.csv") == read_file(tmp / "b/kinematics.csv"));
  // the lift changed: the roller radius is not the file's
  const auto c = run_camopt({"kinematics", kEccentric, "--out", tmp.file("c"), "--step", "2"});
  CHECK(read_file(tmp / "a/kinematics.csv") != read_file(tmp / "c/kinematics.csv"));
  const auto summary = nlohmann::json::parse(read_file(tmp / "a/summary.json"));
  CHECK(summary["overrides"]["connection.disc_roller.b.radius_mm"] == 9);
  CHECK(summary["overrides"]["connection.disc_roller.touch_at_rest"] == true);
  CHECK_FALSE(nlohmann::json::parse(read_file(tmp / "c/summary.json")).contains("overrides"));
}

TEST_CASE("the --set option may come before the subcommand", "[cli][set]") {
  TempDir tmp;
  const auto a = run_camopt(with(kSets, {"kinematics", kEccentric, "--out", tmp.file("a"), "--step", "2"}));
  const auto b = run_camopt({"kinematics", tmp.write("edited.toml", eccentric_by_hand()), "--out", tmp.file("b"),
                             "--step", "2"});
  REQUIRE(a.exit_code == cli_ok);
  REQUIRE(b.exit_code == cli_ok);
  CHECK(read_file(tmp / "a/kinematics.csv") == read_file(tmp / "b/kinematics.csv"));
}

TEST_CASE("dynamics with --set equals the run of the edited file", "[cli][set]") {
  TempDir tmp;
  const std::string edited = tmp.write("edited.toml", eccentric_by_hand());
  const auto a = run_camopt(with({"dynamics", kEccentric, "--rpm", "2000", "--out", tmp.file("a")}, kSets));
  const auto b = run_camopt({"dynamics", edited, "--rpm", "2000", "--out", tmp.file("b")});
  INFO(a.all() << b.all());
  REQUIRE(a.exit_code == cli_ok);
  REQUIRE(b.exit_code == cli_ok);
  CHECK(read_file(tmp / "a/dynamics.csv") == read_file(tmp / "b/dynamics.csv"));
  CHECK(nlohmann::json::parse(read_file(tmp / "a/summary.json"))["overrides"]["connection.disc_roller.b.radius_mm"] == 9);
}

TEST_CASE("validate with --set prints the solved contact of the edited file", "[cli][set]") {
  TempDir tmp;
  const std::string edited = tmp.write("edited.toml", eccentric_by_hand());
  const auto a = run_camopt(with({"validate", kEccentric}, kSets));
  const auto b = run_camopt({"validate", edited});
  REQUIRE(a.exit_code == cli_ok);
  REQUIRE(b.exit_code == cli_ok);
  CHECK(replaced(a.out, kEccentric, "X") == replaced(b.out, edited, "X"));
  CHECK(contains(a.out, "touch at rest: disc_roller: b.center_mm solved ["));
  CHECK(contains(a.out, "(drawn [3, 23.8118], moved "));
}

TEST_CASE("synthesize with --set writes a design.toml that reads back as the override", "[cli][set]") {
  TempDir tmp;
  const fs::path target = tmp / "target.csv";
  REQUIRE(run_camopt({"lift", "--law", "polynomial-345", "--lift", "8", "--duration", "130", "--ramp-height", "0.2",
                      "--ramp-length", "15", "--out", target.string()})
              .exit_code == cli_ok);
  const std::string design = (source_dir() / "designs/roller_finger_follower.toml").string();
  const std::vector<std::string> sets = {"--set", "connection.cam_roller.b.radius_mm=9", "--set",
                                         "connection.cam_roller.touch_at_rest=true", "--set",
                                         "node.finger.mass_kg=0.05"};
  const auto r = run_camopt(with({"synthesize", target.string(), "--design", design, "--out", tmp.file("out")}, sets));
  INFO(r.all());
  REQUIRE(r.exit_code == cli_ok);
  const std::string written = read_file(tmp / "out/design.toml");
  CHECK(contains(written, "#   --set connection.cam_roller.b.radius_mm=9"));
  // the written design read back: the overridden values, and the roller solved as in the run
  const camopt::DesignSpec back = camopt::io::load_design((tmp / "out/design.toml").string());
  camopt::io::DesignDocument doc = camopt::io::DesignDocument::load(design);
  for (std::size_t i = 1; i < sets.size(); i += 2) doc.set(camopt::io::parse_override(sets[i]));
  const camopt::DesignSpec run = doc.spec();
  CHECK(back.connections[0].surface_b.radius_mm == 9);
  CHECK(back.nodes[1].mass_kg == 0.05);
  CHECK(back.connections[0].touch_at_rest);
  // solved against the synthesized profile, which reproduces the lobe's base circle (18 mm)
  // to round-off: 1 mm (0.5 larger radius) below the drawn centre
  CHECK(back.connections[0].surface_b.origin_mm[0] == Approx(run.connections[0].surface_b.origin_mm[0]).margin(1e-9));
  CHECK(back.connections[0].surface_b.origin_mm[1] == Approx(run.connections[0].surface_b.origin_mm[1]).margin(1e-9));
  CHECK(run.connections[0].surface_b.origin_mm[1] == Approx(-27.0).margin(1e-9));
  CHECK(nlohmann::json::parse(read_file(tmp / "out/report.json"))["overrides"]["node.finger.mass_kg"] == 0.05);
}

TEST_CASE("a roller radius override on the finger follower assembles only with touch at rest", "[cli][set]") {
  TempDir tmp;
  const std::string design = (source_dir() / "designs/roller_finger_follower.toml").string();
  const auto ok = run_camopt({"kinematics", design, "--out", tmp.file("a"), "--step", "2", "--set",
                              "connection.cam_roller.b.radius_mm=9.5", "--set",
                              "connection.cam_roller.touch_at_rest=true"});
  INFO(ok.all());
  CHECK(ok.exit_code == cli_ok);
  CHECK_FALSE(contains(ok.err, "warning"));
  // as drawn (the design's touch_at_rest off), the larger roller overlaps the base circle:
  // the drawing check says so
  ExpectWarnings expect({"drawing not assembled: 'finger' solves to", "drawing not assembled: 'valve' solves to"});
  const auto drawn = run_camopt({"kinematics", design, "--out", tmp.file("b"), "--step", "2", "--set",
                                 "connection.cam_roller.b.radius_mm=9.5", "--set",
                                 "connection.cam_roller.touch_at_rest=false"});
  CHECK(contains(drawn.err, "warning: drawing not assembled: 'finger' solves to -2.5996"));
  // and validate refuses it: the valve, held open 1.8 mm, never reaches its seat
  const auto seat = run_camopt({"validate", design, "--set", "connection.cam_roller.b.radius_mm=9.5", "--set",
                                "connection.cam_roller.touch_at_rest=false"});
  CHECK(seat.exit_code == cli_input_error);
  CHECK(contains(seat.err, "the valve never reaches its seat"));
}

TEST_CASE("a bad override is exit 3 naming it", "[cli][set]") {
  struct Case {
    std::string set, message;
  };
  const std::vector<Case> cases = {
      {"node.fingr.mass_kg=0.05", "--set node.fingr.mass_kg=0.05: no [[node]] named \"fingr\" (cam, follower)"},
      {"node.follower.mass_kgg=0.05", "--set node.follower.mass_kgg=0.05: node[1]: unknown key 'mass_kgg'"},
      {"node.follower.origin_mm[2]=1",
       "--set node.follower.origin_mm[2]=1: index 2 is out of range (node.follower.origin_mm has 2 elements)"},
      {"node.follower.mass_kg=true", "--set node.follower.mass_kg=true: node.follower.mass_kg is a number in the file"},
      {"connection.disc_roller.b.radius_mm=-1",
       "--set connection.disc_roller.b.radius_mm=-1: connection[0].b.radius_mm: value -1 must be in [0.001, "
       "1e+06]"},
      {"connection.disc_roller.b.center_mm=[3,10]", "b's centre [3, 10] is inside a's circle"},
  };
  for (const Case& c : cases)
    for (const std::string command : {"validate", "kinematics"}) {
      TempDir tmp;
      std::vector<std::string> args = {command, kEccentric, "--set", c.set, "--set",
                                       "connection.disc_roller.touch_at_rest=true"};
      if (command == "kinematics") args = with(args, {"--out", tmp.file("out")});
      const auto r = run_camopt(args);
      INFO(r.command << "\n" << r.all());
      CHECK(r.exit_code == cli_input_error);
      CHECK(contains(r.err, c.message));
      CHECK_FALSE(fs::exists(tmp / "out"));
    }
  // a command that reads no design refuses --set
  const auto lift = run_camopt({"report", "nothing", "--set", "design.name=x"});
  CHECK(lift.exit_code == cli_input_error);
  CHECK(contains(lift.err, "--set design.name=x: 'report' reads no design file"));
}
