// the wide layout of a long result table: one row per angle, one column group per key
// values, named <quantity>@<key>=<value>; and back to the long table, exactly.
#include "camopt/io/table_layout.hpp"

#include <bit>
#include <catch2/catch.hpp>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "support/input_error.hpp"

using namespace camopt::io;
using camopt::test::input_error_of;
using Catch::Contains;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// rpm x control x cam angle, as the rigid model writes it: 2 speeds, 2 positions, 3 angles;
// each value encodes its row so that a misplaced one shows
Columns long_sample() {
  Columns t;
  t.header = {"rpm", "control_deg", "cam_deg", "force_N", "film_um"};
  t.values.resize(5);
  for (double rpm : {1000.0, 6000.0})
    for (double control : {0.0, 2.5})
      for (double cam : {0.0, 0.5, 1.0}) {
        t.values[0].push_back(rpm);
        t.values[1].push_back(control);
        t.values[2].push_back(cam);
        t.values[3].push_back(rpm + 10 * control + cam);
        t.values[4].push_back(cam == 0.5 ? kNaN : -rpm - cam);
      }
  t.may_be_empty = {false, false, false, false, true};
  return t;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<std::uint64_t>(a[i]) != std::bit_cast<std::uint64_t>(b[i])) return false;
  return true;
}

}  // namespace

TEST_CASE("table layout: the wide table has a column group per key values, named with them", "[io][layout]") {
  const Columns t = long_sample();
  const Columns w = wide_table(t, 2);
  CHECK(w.header == std::vector<std::string>{"cam_deg", "force_N@rpm=1000@control_deg=0",
                                             "film_um@rpm=1000@control_deg=0", "force_N@rpm=1000@control_deg=2.5",
                                             "film_um@rpm=1000@control_deg=2.5", "force_N@rpm=6000@control_deg=0",
                                             "film_um@rpm=6000@control_deg=0", "force_N@rpm=6000@control_deg=2.5",
                                             "film_um@rpm=6000@control_deg=2.5"});
  CHECK(same_bits(w.values[0], {0.0, 0.5, 1.0}));
  // 6000 rpm, control 2.5: rows 9..11 of the long table
  CHECK(same_bits(w.values[7], {6025.0, 6025.5, 6026.0}));
  CHECK(same_bits(w.values[8], {-6000.0, kNaN, -6001.0}));
  CHECK(w.may_be_empty == std::vector<bool>{false, false, true, false, true, false, true, false, true});
}

TEST_CASE("table layout: the long table of the wide one is the original, bit for bit", "[io][layout]") {
  const Columns t = long_sample();
  const Columns back = long_table(wide_table(t, 2), "w.csv");
  REQUIRE(back.header == t.header);
  for (std::size_t c = 0; c < t.values.size(); ++c) {
    INFO(t.header[c]);
    CHECK(same_bits(back.values[c], t.values[c]));
  }
}

TEST_CASE("table layout: a wide table whose names break the layout is an input error", "[io][layout]") {
  Columns w = wide_table(long_sample(), 2);
  w.header[3] = "force_N@rpm=1000@control_deg";
  CHECK_THAT(input_error_of([&] { (void)long_table(w, "w.csv"); }),
             Contains("w.csv: column 'force_N@rpm=1000@control_deg': 'control_deg' is not <key column>=<number>"));
  w = wide_table(long_sample(), 2);
  w.header[4] = "lift_mm@rpm=1000@control_deg=2.5";
  CHECK_THAT(input_error_of([&] { (void)long_table(w, "w.csv"); }),
             Contains("the groups of a wide table carry the same quantities in the same order"));
}
