// NumPy .npz archives of result tables: the zip and .npy layouts checked byte by byte against
// the published formats, values read back bit for bit, and damaged archives refused by name.
#include "camopt/io/npz.hpp"

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "support/input_error.hpp"

using namespace camopt::io;
using camopt::test::input_error_of;
using Catch::Contains;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// a table with the values a writer can get wrong: -0, the extremes, a subnormal, an empty cell
Columns sample_table() {
  Columns t;
  t.header = {"cam_deg", "lift_mm", "film_thickness_um"};
  t.values = {{0.0, 0.5, 1.0, 1.5},
              {-0.0, std::numeric_limits<double>::max(), -std::numeric_limits<double>::denorm_min(), 0.1},
              {kNaN, 1e-300, 2.5, kNaN}};
  t.may_be_empty = {false, false, true};
  return t;
}

std::uint32_t u32_at(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(b[at + static_cast<std::size_t>(k)]);
  return v;
}

}  // namespace

TEST_CASE("npz: CRC-32 gives the zip format's check value", "[io][npz]") {
  // the catalogue check value of CRC-32/ISO-HDLC over "123456789"
  CHECK(crc32("123456789") == 0xCBF43926u);
  CHECK(crc32("") == 0u);
}

TEST_CASE("npz: the archive is a stored zip of .npy float64 vectors, read back bit for bit", "[io][npz]") {
  const Columns t = sample_table();
  const std::string bytes = format_npz(t);
  // the first member: a zip local header (signature, stored), its name, then the .npy magic
  // and a header dict padded to 64 bytes
  REQUIRE(u32_at(bytes, 0) == 0x04034b50u);
  CHECK(bytes[8] == 0);  // compression: stored
  const std::size_t name_size = static_cast<unsigned char>(bytes[26]);
  CHECK(bytes.substr(30, name_size) == "cam_deg.npy");
  const std::string npy = bytes.substr(30 + name_size);
  CHECK(npy.substr(0, 8) == std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header = 10 + static_cast<unsigned char>(npy[8]);
  CHECK(header % 64 == 0);
  CHECK(npy.substr(10, header - 10).find("{'descr': '<f8', 'fortran_order': False, 'shape': (4,), }") == 0);
  CHECK(npy[header - 1] == '\n');
  double first[4];
  std::memcpy(first, npy.data() + header, sizeof first);
  CHECK(std::bit_cast<std::uint64_t>(first[1]) == std::bit_cast<std::uint64_t>(0.5));
  // the end record: 3 members
  CHECK(u32_at(bytes, bytes.size() - 22) == 0x06054b50u);
  CHECK(static_cast<unsigned char>(bytes[bytes.size() - 22 + 10]) == 3);

  const Columns back = parse_npz(bytes, "t.npz");
  REQUIRE(back.header == t.header);
  for (std::size_t c = 0; c < t.values.size(); ++c)
    for (std::size_t r = 0; r < t.values[c].size(); ++r) {
      INFO(t.header[c] << " row " << r);
      // -0 is written as 0, as the CSV writes it; a NaN stays a NaN
      const double expected = t.values[c][r] + 0.0;
      CHECK(std::bit_cast<std::uint64_t>(back.values[c][r]) == std::bit_cast<std::uint64_t>(expected));
    }
  CHECK(back.may_be_empty == std::vector<bool>{false, false, true});
}

TEST_CASE("npz: a non-finite value outside an empty cell is a bug", "[io][npz]") {
  Columns t = sample_table();
  t.values[1][2] = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(format_npz(t), Contains("column 'lift_mm' row 3"));
}

TEST_CASE("npz: a truncated or damaged archive is an input error naming the file and the fault", "[io][npz]") {
  const std::string bytes = format_npz(sample_table());
  // cut anywhere: the end record is gone
  for (std::size_t keep : {std::size_t{0}, std::size_t{10}, bytes.size() / 2, bytes.size() - 1}) {
    INFO("kept " << keep << " bytes");
    const std::string message = input_error_of([&] { (void)parse_npz(bytes.substr(0, keep), "out/kinematics.npz"); });
    CHECK_THAT(message, Contains("out/kinematics.npz: not a .npz archive as camopt writes it"));
    CHECK_THAT(message, Contains("truncated"));
  }
  // one data byte changed: the member's CRC no longer matches
  std::string damaged = bytes;
  damaged[30 + 11 + 64 + 9] ^= 0x40;
  CHECK_THAT(input_error_of([&] { (void)parse_npz(damaged, "d.npz"); }),
             Contains("member 'cam_deg.npy': CRC-32 does not match"));
  // not a zip at all
  CHECK_THAT(input_error_of([&] { (void)parse_npz(std::string(100, 'x'), "x.npz"); }), Contains("no zip end record"));
}
