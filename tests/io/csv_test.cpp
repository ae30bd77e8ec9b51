#include "camopt/io/csv.hpp"

#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "camopt/core/error.hpp"
#include "support/input_error.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using camopt::InputError;
using namespace camopt::io;
using Catch::Contains;

using camopt::test::TempDir;

namespace {



// one lift table, written with each delimiter
const char* const kCommaTable = "cam_deg,lift_mm\n0,0\n1.5,0.25\n3,1e-1\n";
const char* const kSemicolonTable = "cam_deg;lift_mm\n0;0\n1.5;0.25\n3;1e-1\n";
const char* const kWhitespaceTable = "cam_deg   lift_mm\n  0\t0\n1.5 \t 0.25\n3    1e-1   \n";

void check_small_table(const CsvTable& table) {
  REQUIRE(table.columns == std::vector<std::string>{"cam_deg", "lift_mm"});
  REQUIRE(table.rows() == 3);
  CHECK(table.values[0] == std::vector<double>{0.0, 1.5, 3.0});
  CHECK(table.values[1] == std::vector<double>{0.0, 0.25, 0.1});
  CHECK(table.lines == std::vector<int>{2, 3, 4});
}

}  // namespace

TEST_CASE("parse_csv reads a comma separated table", "[io][csv]") {
  check_small_table(parse_csv(kCommaTable, "lift.csv"));
}

TEST_CASE("parse_csv reads a semicolon separated table", "[io][csv]") {
  check_small_table(parse_csv(kSemicolonTable, "lift.csv"));
}

TEST_CASE("parse_csv reads a whitespace separated table with mixed tabs and spaces", "[io][csv]") {
  check_small_table(parse_csv(kWhitespaceTable, "lift.dat"));
}

TEST_CASE("parse_csv trims cells and accepts signs and exponents", "[io][csv]") {
  const auto table = parse_csv("  cam_deg ,  lift_mm  \n -2.5 , +1.25E+1 \n0 ,  -0\n", "lift.csv");
  REQUIRE(table.columns == std::vector<std::string>{"cam_deg", "lift_mm"});
  CHECK(table.values[0] == std::vector<double>{-2.5, 0.0});
  CHECK(table.values[1] == std::vector<double>{12.5, 0.0});
}

TEST_CASE("parse_csv skips comments and blank lines and keeps file line numbers", "[io][csv]") {
  const char* text =
      "# lift table [mm]\n"
      "   # indented comment\n"
      "\n"
      "cam_deg,lift_mm   # header with a trailing comment\n"
      "  \t \n"
      "0,0\n"
      "# between rows\n"
      "10,2.5 # trailing comment\n";
  const auto table = parse_csv(text, "lift.csv");
  REQUIRE(table.columns == std::vector<std::string>{"cam_deg", "lift_mm"});
  CHECK(table.values[1] == std::vector<double>{0.0, 2.5});
  CHECK(table.lines == std::vector<int>{6, 8});
}

TEST_CASE("parse_csv handles CRLF line endings", "[io][csv]") {
  const auto table = parse_csv("cam_deg,lift_mm\r\n0,0\r\n# note\r\n1.5,0.25\r\n3,1e-1\r\n", "lift.csv");
  REQUIRE(table.columns == std::vector<std::string>{"cam_deg", "lift_mm"});
  CHECK(table.values[1] == std::vector<double>{0.0, 0.25, 0.1});
  CHECK(table.lines == std::vector<int>{2, 4, 5});
}

TEST_CASE("parse_csv skips a UTF-8 byte order mark", "[io][csv]") {
  const auto table = parse_csv(std::string("\xEF\xBB\xBF") + kCommaTable, "lift.csv");
  check_small_table(table);
  CHECK(table.find("cam_deg") == 0u);
}

TEST_CASE("parse_csv handles a last line without newline", "[io][csv]") {
  const auto table = parse_csv("cam_deg lift_mm\n0 1\n2 3", "lift.dat");
  CHECK(table.values[1] == std::vector<double>{1.0, 3.0});
}

TEST_CASE("CsvTable column lookup is case-insensitive and names missing columns", "[io][csv]") {
  const auto table = parse_csv("Cam_Deg,Lift_MM,force_N\n0,1,2\n", "lift.csv");
  CHECK(table.find("cam_deg") == 0u);
  CHECK(table.find("LIFT_mm") == 1u);
  CHECK_FALSE(table.find("velocity").has_value());
  CHECK(table.column("FORCE_N") == std::vector<double>{2.0});
  CHECK(table.require_one_of({"valve_lift_mm", "lift_mm"}, "lift") == 1u);

  const auto missing = camopt::test::input_error_of([&] { table.column("velocity_mm_per_deg"); });
  CHECK_THAT(missing, Contains("lift.csv") && Contains("'velocity_mm_per_deg'") &&
                          Contains("Cam_Deg, Lift_MM, force_N"));
  const auto none = camopt::test::input_error_of([&] { table.require_one_of({"valve_lift_mm", "tappet_lift_mm"}, "lift"); });
  CHECK_THAT(none, Contains("lift.csv") && Contains("no lift column") &&
                       Contains("valve_lift_mm, tappet_lift_mm") && Contains("Cam_Deg, Lift_MM, force_N"));
}

TEST_CASE("parse_csv rejects a cell that is not a number with file, line, column and text", "[io][csv]") {
  const char* text =
      "# comment\n"
      "cam_deg,lift_mm\n"
      "0,0\n"
      "1,0.1\n"
      "\n"
      "2,0.2\n"
      "3,0.3abc\n";
  REQUIRE_THROWS_AS(parse_csv(text, "lift.csv"), InputError);
  REQUIRE_THROWS_WITH(parse_csv(text, "lift.csv"),
                      Contains("lift.csv:7: column 'lift_mm' value '0.3abc' is not a number"));
}

TEST_CASE("parse_csv rejects a decimal comma in a semicolon table", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("cam_deg;lift_mm\n0;0\n1;0,5\n", "lift.csv"),
                      Contains("lift.csv:3: column 'lift_mm' value '0,5' is not a number"));
}

TEST_CASE("parse_csv rejects NaN and infinite values", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("cam_deg,lift_mm\n0,0\n1,nan\n", "lift.csv"),
                      Contains("lift.csv:3: column 'lift_mm' value 'nan' is not finite"));
  REQUIRE_THROWS_WITH(parse_csv("cam_deg,lift_mm\n0,0\n1,1\n-inf,2\n", "lift.csv"),
                      Contains("lift.csv:4: column 'cam_deg' value '-inf' is not finite"));
  REQUIRE_THROWS_WITH(parse_csv("cam_deg,lift_mm\n0,1e400\n", "lift.csv"),
                      Contains("lift.csv:2: column 'lift_mm' value '1e400' is not finite"));
}

TEST_CASE("parse_csv rejects a row with missing cells", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("a,b,c\n1,2,3\n4,5\n", "table.csv"),
                      Contains("table.csv:3: expected 3 cells (columns: a, b, c), found 2"));
  REQUIRE_THROWS_WITH(parse_csv("a b c\n1 2 3\n\n4\n", "table.dat"),
                      Contains("table.dat:4: expected 3 cells (columns: a, b, c), found 1"));
}

TEST_CASE("parse_csv rejects a row with extra cells", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("a;b\n1;2\n3;4;5\n", "table.csv"),
                      Contains("table.csv:3: expected 2 cells (columns: a, b), found 3"));
  // a trailing delimiter is an extra (empty) cell
  REQUIRE_THROWS_WITH(parse_csv("a,b\n1,2,\n", "table.csv"),
                      Contains("table.csv:2: expected 2 cells (columns: a, b), found 3"));
}

TEST_CASE("parse_csv rejects an empty cell", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("cam_deg,lift_mm,force_N\n0,1,2\n1, ,3\n", "lift.csv"),
                      Contains("lift.csv:3: column 'lift_mm' is empty"));
}

TEST_CASE("parse_csv rejects an empty file", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("", "empty.csv"), Contains("empty.csv") && Contains("empty file"));
  REQUIRE_THROWS_WITH(parse_csv(" \r\n\n\t\n", "empty.csv"), Contains("empty.csv") && Contains("empty file"));
  REQUIRE_THROWS_WITH(parse_csv("\xEF\xBB\xBF", "empty.csv"), Contains("empty.csv") && Contains("empty file"));
}

TEST_CASE("parse_csv rejects a file with only comments", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("# just a note\n\n  # another\n", "notes.csv"),
                      Contains("notes.csv") && Contains("no header line"));
}

TEST_CASE("parse_csv rejects a header without data rows", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("cam_deg,lift_mm\n# no rows yet\n", "lift.csv"),
                      Contains("lift.csv") && Contains("no data rows") && Contains("cam_deg, lift_mm"));
}

TEST_CASE("parse_csv rejects a numeric first line instead of a header", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("# raw .dat file\n0 0.0055\n1 0.0056\n", "Lv_I-mb.dat"),
                      Contains("Lv_I-mb.dat:2") && Contains("header") && Contains("'0 0.0055'"));
}

TEST_CASE("parse_csv rejects duplicate column names", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("cam_deg,lift_mm,LIFT_MM\n0,1,2\n", "lift.csv"),
                      Contains("lift.csv:1") && Contains("duplicate column name 'LIFT_MM'"));
}

TEST_CASE("parse_csv rejects an unnamed header column", "[io][csv]") {
  REQUIRE_THROWS_WITH(parse_csv("cam_deg,,lift_mm\n0,1,2\n", "lift.csv"),
                      Contains("lift.csv:1") && Contains("column 2 has no name"));
}

TEST_CASE("require_strictly_increasing rejects a repeated angle", "[io][csv]") {
  const auto table = parse_csv("cam_deg,lift_mm\n0,0\n# c\n0.5,1\n0.5,2\n", "lift.csv");
  REQUIRE_THROWS_WITH(require_strictly_increasing(table, 0),
                      Contains("lift.csv:5: column 'cam_deg' value 0.5 is not greater than the previous "
                               "value 0.5 (line 4); angles must be strictly increasing"));
}

TEST_CASE("require_strictly_increasing rejects a decreasing angle", "[io][csv]") {
  const auto table = parse_csv("crank_deg,lift_mm\n-10,0\n-2.5,1\n-3,2\n", "lift.csv");
  REQUIRE_THROWS_WITH(require_strictly_increasing(table, 0),
                      Contains("lift.csv:4: column 'crank_deg' value -3 is not greater than the previous "
                               "value -2.5 (line 3)"));
  // the value column may decrease
  REQUIRE_NOTHROW(require_strictly_increasing(parse_csv("cam_deg,lift_mm\n0,2\n1,1\n", "ok.csv"), 0));
}

TEST_CASE("read_angle_table detects a cam angle basis", "[io][csv][angle]") {
  for (const char* name : {"cam_deg", "cam_angle_deg", "CAM_Angle_Deg"}) {
    const auto csv = parse_csv(std::string(name) + ",valve_lift_mm\n0,0\n1,0.5\n", "lift.csv");
    const auto table = read_angle_table(csv, {"lift_mm", "valve_lift_mm"});
    CHECK(table.basis == AngleBasis::cam);
    CHECK(table.angle_column == name);
    CHECK(table.value_column == "valve_lift_mm");
    CHECK(table.angle_deg == std::vector<double>{0.0, 1.0});
    CHECK(table.value == std::vector<double>{0.0, 0.5});
    CHECK(table.lines == std::vector<int>{2, 3});
    CHECK(table.file == "lift.csv");
  }
  CHECK(std::string(to_string(AngleBasis::cam)) == "cam");
}

TEST_CASE("read_angle_table detects a crank angle basis", "[io][csv][angle]") {
  for (const char* name : {"crank_deg", "crank_angle_deg", "Crank_Deg"}) {
    const auto csv = parse_csv(std::string("force_N,") + name + ",lift_mm\n7,0,0\n8,2,0.5\n", "lift.csv");
    const auto table = read_angle_table(csv, {"lift_mm"});
    CHECK(table.basis == AngleBasis::crank);
    CHECK(table.angle_column == name);
    CHECK(table.angle_deg == std::vector<double>{0.0, 2.0});
  }
  CHECK(std::string(to_string(AngleBasis::crank)) == "crank");
}

TEST_CASE("read_angle_table rejects an angle column without basis", "[io][csv][angle]") {
  for (const char* name : {"angle_deg", "angle", "polar_angle_deg", "Angle"}) {
    const auto csv = parse_csv(std::string(name) + ",lift_mm\n0,0\n1,0.5\n", "lift.csv");
    const auto message = camopt::test::input_error_of([&] { read_angle_table(csv, {"lift_mm"}); });
    CHECK_THAT(message, Contains("lift.csv") && Contains(std::string("'") + name + "'") &&
                            Contains("basis must be explicit") && Contains("cam_deg, cam_angle_deg") &&
                            Contains("crank_deg, crank_angle_deg"));
  }
}

TEST_CASE("read_angle_table rejects both cam and crank angle columns", "[io][csv][angle]") {
  const auto csv = parse_csv("cam_deg,crank_deg,lift_mm\n0,0,0\n1,2,0.5\n", "lift.csv");
  REQUIRE_THROWS_WITH(read_angle_table(csv, {"lift_mm"}),
                      Contains("lift.csv") && Contains("more than one angle column") &&
                          Contains("'cam_deg'") && Contains("'crank_deg'"));
}

TEST_CASE("read_angle_table rejects a table without angle or value column", "[io][csv][angle]") {
  const auto no_angle = parse_csv("time_s,lift_mm\n0,0\n1,0.5\n", "lift.csv");
  REQUIRE_THROWS_WITH(read_angle_table(no_angle, {"lift_mm"}),
                      Contains("lift.csv") && Contains("no angle column") && Contains("time_s, lift_mm"));
  const auto no_value = parse_csv("cam_deg,force_N\n0,0\n1,0.5\n", "lift.csv");
  REQUIRE_THROWS_WITH(read_angle_table(no_value, {"lift_mm", "valve_lift_mm"}),
                      Contains("lift.csv") && Contains("lift_mm, valve_lift_mm"));
}

TEST_CASE("read_angle_table needs two rows and increasing angles", "[io][csv][angle]") {
  const auto one_row = parse_csv("cam_deg,lift_mm\n0,0\n", "lift.csv");
  REQUIRE_THROWS_WITH(read_angle_table(one_row, {"lift_mm"}),
                      Contains("lift.csv") && Contains("at least 2 rows, found 1"));
  const auto repeated = parse_csv("cam_deg,lift_mm\n0,0\n1,0.5\n1,0.6\n", "lift.csv");
  REQUIRE_THROWS_WITH(read_angle_table(repeated, {"lift_mm"}),
                      Contains("lift.csv:4: column 'cam_deg' value 1 is not greater"));
}

TEST_CASE("require_full_cycle accepts exactly one cycle", "[io][csv][angle]") {
  const auto table_over = [](double first, double last, double step, const char* angle) {
    std::string text = std::string(angle) + ",lift_mm\n";
    for (double a = first; a <= last + 1e-9; a += step) text += std::to_string(a) + ",0\n";
    return read_angle_table(parse_csv(text, "cycle.csv"), {"lift_mm"});
  };
  // closed (first and last coincide modulo the period) and open (last step wraps)
  CHECK_NOTHROW(require_full_cycle(table_over(0, 360, 2, "cam_deg"), 360));
  CHECK_NOTHROW(require_full_cycle(table_over(0, 358, 2, "cam_deg"), 360));
  CHECK_NOTHROW(require_full_cycle(table_over(-180, 179.5, 0.5, "cam_deg"), 360));
  CHECK_NOTHROW(require_full_cycle(table_over(0, 720, 5, "crank_deg"), 720));
}

TEST_CASE("require_full_cycle rejects a partial or overlong table", "[io][csv][angle]") {
  const auto table = read_angle_table(parse_csv("crank_deg,lift_mm\n0,0\n300,1\n350,0\n", "part.csv"),
                                      {"lift_mm"});
  REQUIRE_THROWS_WITH(require_full_cycle(table, 720),
                      Contains("part.csv") && Contains("0 to 350 deg crank") && Contains("720 deg crank"));

  const auto two_turns = read_angle_table(parse_csv("cam_deg,lift_mm\n0,0\n360,1\n400,0\n", "long.csv"),
                                          {"lift_mm"});
  REQUIRE_THROWS_WITH(require_full_cycle(two_turns, 360),
                      Contains("long.csv") && Contains("0 to 400 deg cam") && Contains("more than one cycle") &&
                          Contains("360 deg cam"));
}

TEST_CASE("write_csv round-trips exact doubles", "[io][csv][write]") {
  const TempDir dir;
  const std::string path = dir.file("roundtrip.csv");
  const std::vector<double> angle = {-84.0, 0.1, 1.0 / 3.0, std::numbers::pi, 1e300};
  const std::vector<double> lift = {-1e-300, 2.0 / 3.0, 7.443649, std::numeric_limits<double>::denorm_min(),
                                    -0.0};
  write_csv(path, {"cam_deg", "lift_mm"}, {angle, lift});

  const auto table = read_csv(path);
  REQUIRE(table.columns == std::vector<std::string>{"cam_deg", "lift_mm"});
  CHECK(table.values[0] == angle);
  CHECK(table.values[1] == lift);
  CHECK(table.lines == std::vector<int>{2, 3, 4, 5, 6});
}

TEST_CASE("write_csv writes each number as its shortest round-trip text", "[io][csv][write]") {
  const TempDir dir;
  const std::string path = dir.file("short.csv");
  write_csv(path, {"cam_deg", "lift_mm"}, {{0.1, 2.0, 17.6}, {1.0 / 3.0, 12345.678, 1e-9}});
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(text == "cam_deg,lift_mm\n0.1,0.3333333333333333\n2,12345.678\n17.6,1e-09\n");
}

TEST_CASE("format_csv and parse_csv round-trip random doubles bit for bit", "[io][csv][write]") {
  // every exponent and mantissa: random bit patterns that are finite and not -0 (written as 0),
  std::mt19937_64 random(20240611);
  std::vector<double> a, b;
  while (a.size() < 20000) {
    const std::uint64_t bits = random();
    double v = 0;
    std::memcpy(&v, &bits, sizeof v);
    if (!std::isfinite(v) || (v == 0 && std::signbit(v))) continue;
    a.push_back(v);
    // and values of a table's scale, uniform in [-20, 20) mm
    b.push_back(std::ldexp(static_cast<double>(random() >> 11), -53) * 40.0 - 20.0);
  }
  const auto table = parse_csv(format_csv({"cam_deg", "lift_mm"}, {a, b}), "random.csv");
  REQUIRE(table.rows() == a.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    differ += std::memcmp(&table.values[0][i], &a[i], sizeof(double)) != 0;
    differ += std::memcmp(&table.values[1][i], &b[i], sizeof(double)) != 0;
  }
  CHECK(differ == 0);
}

TEST_CASE("format_csv on several threads writes the one-thread text, rows in order", "[io][csv][write]") {
  // more rows than one chunk of the parallel writer, with -0 (written 0) and empty cells
  std::mt19937_64 random(7);
  Columns table{{"cam_deg", "lift_mm", "film_um"}, {{}, {}, {}}, {false, false, true}};
  for (int r = 0; r < 20011; ++r) {
    table.values[0].push_back(0.25 * r);
    table.values[1].push_back(r % 7 == 0 ? -0.0 : std::ldexp(static_cast<double>(random() >> 11), -53) - 0.5);
    table.values[2].push_back(r % 5 == 0 ? std::numeric_limits<double>::quiet_NaN() : 1.0 / (r + 1));
  }
  const std::string one = format_csv(table, 1);
  CHECK(format_csv(table, 2) == one);
  CHECK(format_csv(table, 3) == one);
  // the rows in order: the line of row 12345 (in the fourth chunk) is its values' text
  const auto lines = [&one] {
    std::vector<std::string> out;
    for (std::size_t at = 0, end; (end = one.find('\n', at)) != std::string::npos; at = end + 1)
      out.push_back(one.substr(at, end - at));
    return out;
  }();
  REQUIRE(lines.size() == 20012);
  CHECK(lines[1 + 12345] == "3086.25,-0.22861772838715355,");
  CHECK(lines[1 + 7] == "1.75,0,0.125");
  CHECK(lines[1 + 10] == "2.5,-0.24284193123600306,");
}

TEST_CASE("write_csv refuses non-finite values", "[io][csv][write]") {
  const TempDir dir;
  const std::string path = dir.file("bad.csv");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_AS(write_csv(path, {"cam_deg", "lift_mm"}, {{0, 1}, {0, nan}}), std::logic_error);
  REQUIRE_THROWS_WITH(write_csv(path, {"cam_deg", "lift_mm"}, {{0, 1}, {0, nan}}),
                      Contains("column 'lift_mm' row 2"));
  CHECK_FALSE(fs::exists(path));
  CHECK(fs::is_empty(dir.path()));
}

TEST_CASE("read_csv names a file that cannot be read", "[io][csv]") {
  const TempDir dir;
  const std::string path = dir.file("missing.csv");
  REQUIRE_THROWS_WITH(read_csv(path), Contains("missing.csv") && Contains("cannot read"));
  REQUIRE_THROWS_WITH(read_csv(dir.path().string()), Contains("cannot read") && Contains("directory"));
}

TEST_CASE("real data: flat tappet lift table in cam degrees", "[io][csv][real]") {
  // max 7.443649 mm at -1 deg (checked with awk against the file)
  const auto csv = read_csv(CAMOPT_SHARED_DATA_DIR "/ehl_cam_tappet_asfand/CamAngle_vs_Lift_smooth.csv");
  const auto table = read_angle_table(csv, {"tappet_lift_mm", "lift_mm"});
  CHECK(table.basis == AngleBasis::cam);
  CHECK(table.angle_column == "cam_angle_deg");
  CHECK(table.value_column == "tappet_lift_mm");
  REQUIRE(table.angle_deg.size() == 329);
  CHECK(table.angle_deg.front() == -84.0);
  CHECK(table.angle_deg.back() == 80.0);
  const auto peak = std::max_element(table.value.begin(), table.value.end());
  CHECK(*peak == 7.443649);
  CHECK(table.angle_deg[static_cast<std::size_t>(peak - table.value.begin())] == -1.0);
  CHECK(table.lines.front() == 2);
  CHECK(table.lines.back() == 330);
}

TEST_CASE("real data: ICESym intake valve lift in crank degrees covers one cycle", "[io][csv][real]") {
  const auto csv = read_csv(CAMOPT_SHARED_DATA_DIR "/icesym_boscarol/Lv_I-mb.csv");
  const auto table = read_angle_table(csv, {"valve_lift_mm", "lift_mm"});
  CHECK(table.basis == AngleBasis::crank);
  CHECK(table.angle_column == "crank_angle_deg");
  REQUIRE(table.angle_deg.size() == 153);
  CHECK(table.angle_deg.front() == 0.0);
  CHECK(table.angle_deg.back() == 720.0);
  CHECK(*std::max_element(table.value.begin(), table.value.end()) == 14.195);
  CHECK_NOTHROW(require_full_cycle(table, 720.0));
  CHECK_THROWS_WITH(require_full_cycle(table, 360.0), Contains("Lv_I-mb.csv") && Contains("more than one cycle"));
}

TEST_CASE("format_csv writes a negative zero as 0 and every digit of the others", "[io][csv]") {
  const std::string text = camopt::io::format_csv({"cam_deg", "lift_mm"}, {{0.0, 1.0}, {-0.0, -1.234567890123}});
  CHECK(text == "cam_deg,lift_mm\n0,0\n1,-1.234567890123\n");
}

TEST_CASE("format_csv writes NaN as an empty cell only in a column that may be empty", "[io][csv]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  using camopt::io::format_csv;
  CHECK(format_csv({"cam_deg", "film_thickness_um", "lambda"}, {{0.0, 1.0}, {0.5, nan}, {nan, 4.0}}, {false, true, true}) ==
        "cam_deg,film_thickness_um,lambda\n0,0.5,\n1,,4\n");
  // elsewhere a NaN is still a kernel bug, and so is an infinity in a column that may be empty
  CHECK_THROWS_AS(format_csv({"cam_deg", "film_thickness_um"}, {{0.0, nan}, {0.5, 1.0}}, {false, true}), std::logic_error);
  CHECK_THROWS_WITH(format_csv({"cam_deg", "film_thickness_um"}, {{0.0, 1.0}, {0.5, inf}}, {false, true}),
                    "write_csv: non-finite value in column 'film_thickness_um' row 2");
}
