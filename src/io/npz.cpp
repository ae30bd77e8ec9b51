// NumPy .npz archives of result tables: a zip (stored, no compression, no zip64) of .npy
// arrays, format 1.0 (numpy.lib.format), little-endian float64.
#include "camopt/io/npz.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "camopt/core/error.hpp"
#include "camopt/io/input_file.hpp"

namespace camopt::io {
namespace {

static_assert(std::endian::native == std::endian::little, "the .npy data are written as the host's doubles");

// zip record signatures and sizes (PKWARE APPNOTE 4.3.7, 4.3.12, 4.3.16)
constexpr std::uint32_t kLocalSignature = 0x04034b50, kCentralSignature = 0x02014b50, kEndSignature = 0x06054b50;
constexpr std::size_t kLocalSize = 30, kCentralSize = 46, kEndSize = 22;
constexpr std::uint16_t kZipVersion = 20;        // 2.0: stored members, as numpy writes them
constexpr std::uint16_t kDosDate = (0 << 9) | (1 << 5) | 1;  // 1980-01-01: the same bytes every run
constexpr std::uint64_t kZipLimit = 0xffffffffu;  // sizes and offsets without zip64
// the .npy magic, version 1.0 and the dictionary of a float64 vector; the header is padded
// with spaces to a multiple of 64 bytes, as numpy pads it
constexpr std::string_view kNpyMagic = "\x93NUMPY";
constexpr std::size_t kNpyAlign = 64;

const std::array<std::uint32_t, 256>& crc_table() {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  return table;
}

void put16(std::string& out, std::uint16_t v) {
  out.push_back(static_cast<char>(v & 0xff));
  out.push_back(static_cast<char>(v >> 8));
}
void put32(std::string& out, std::uint32_t v) {
  put16(out, static_cast<std::uint16_t>(v & 0xffff));
  put16(out, static_cast<std::uint16_t>(v >> 16));
}
std::uint16_t get16(std::string_view b, std::size_t at) {
  return static_cast<std::uint16_t>(static_cast<unsigned char>(b[at]) | static_cast<unsigned char>(b[at + 1]) << 8);
}
std::uint32_t get32(std::string_view b, std::size_t at) {
  return static_cast<std::uint32_t>(get16(b, at)) | static_cast<std::uint32_t>(get16(b, at + 2)) << 16;
}

// the .npy header of a float64 vector of n values
std::string npy_header(std::size_t n) {
  std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(n) + ",), }";
  const std::size_t unpadded = kNpyMagic.size() + 4 + dict.size() + 1;
  dict.append((kNpyAlign - unpadded % kNpyAlign) % kNpyAlign, ' ');
  dict.push_back('\n');
  std::string out(kNpyMagic);
  out.push_back('\x01');
  out.push_back('\x00');
  put16(out, static_cast<std::uint16_t>(dict.size()));
  return out + dict;
}

// a zip record header of a stored member: local, or central (with the local header's offset)
void put_member_header(std::string& out, bool central, const std::string& name, std::uint32_t crc,
                       std::uint32_t size, std::uint32_t offset) {
  put32(out, central ? kCentralSignature : kLocalSignature);
  if (central) put16(out, kZipVersion);  // made by
  put16(out, kZipVersion);               // needed to extract
  put16(out, 0);                         // flags
  put16(out, 0);                         // stored
  put16(out, 0);                         // time
  put16(out, kDosDate);
  put32(out, crc);
  put32(out, size);  // compressed
  put32(out, size);
  put16(out, static_cast<std::uint16_t>(name.size()));
  put16(out, 0);  // extra field
  if (central) {
    put16(out, 0);  // comment
    put16(out, 0);  // disk
    put16(out, 0);  // internal attributes
    put32(out, 0);  // external attributes
    put32(out, offset);
  }
  out += name;
}

// the values of column c as written: -0 as 0, every value finite or an empty cell's NaN
void check_column(const Columns& table, std::size_t c) {
  const bool may_be_empty = !table.may_be_empty.empty() && table.may_be_empty[c];
  const auto& column = table.values[c];
  for (std::size_t r = 0; r < column.size(); ++r)
    if (!std::isfinite(column[r]) && !(may_be_empty && std::isnan(column[r])))
      throw std::logic_error("format_npz: non-finite value in column '" + table.header[c] + "' row " +
                             std::to_string(r + 1));
}

[[noreturn]] void bad(const std::string& file, const std::string& what) {
  throw InputError(file + ": not a .npz archive as camopt writes it: " + what);
}

// the values of one member's .npy bytes
std::vector<double> parse_npy(std::string_view npy, const std::string& file, const std::string& member) {
  const std::string where = "member '" + member + "'";
  if (npy.size() < kNpyMagic.size() + 4 || npy.substr(0, kNpyMagic.size()) != kNpyMagic)
    bad(file, where + " is not a .npy array (no NUMPY magic)");
  if (npy[6] != '\x01' || npy[7] != '\x00') bad(file, where + ": .npy version other than 1.0");
  const std::size_t header_end = kNpyMagic.size() + 4 + get16(npy, 8);
  if (header_end > npy.size()) bad(file, where + ": its header runs past the member (truncated)");
  const std::string_view dict = npy.substr(kNpyMagic.size() + 4, header_end - kNpyMagic.size() - 4);
  const std::string_view shape_key = "'shape': (";
  const std::size_t shape = dict.find(shape_key);
  if (dict.find("'descr': '<f8'") == std::string_view::npos || dict.find("'fortran_order': False") == std::string_view::npos ||
      shape == std::string_view::npos)
    bad(file, where + ": not a little-endian float64 vector ('" + std::string(dict.substr(0, dict.find('\n'))) + "')");
  std::size_t n = 0, at = shape + shape_key.size();
  for (; at < dict.size() && dict[at] >= '0' && dict[at] <= '9'; ++at) n = n * 10 + static_cast<std::size_t>(dict[at] - '0');
  if (dict.substr(at, 3) != ",),") bad(file, where + ": not one-dimensional");
  if (npy.size() - header_end != n * sizeof(double))
    bad(file, where + ": " + std::to_string(npy.size() - header_end) + " data bytes for " + std::to_string(n) +
                  " float64 values");
  std::vector<double> values(n);
  if (n > 0) std::memcpy(values.data(), npy.data() + header_end, n * sizeof(double));
  return values;
}

// the end of central directory record: its offset (no archive comment is written, but one is
// allowed)
std::size_t find_end_record(std::string_view b, const std::string& file) {
  if (b.size() < kEndSize) bad(file, std::to_string(b.size()) + " bytes, shorter than a zip's end record (truncated)");
  for (std::size_t at = b.size() - kEndSize + 1; at-- > 0 && b.size() - at <= kEndSize + 0xffff;)
    if (get32(b, at) == kEndSignature) return at;
  bad(file, "no zip end record (truncated, or not a zip archive)");
}

}  // namespace

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc) {
  const auto& table = crc_table();
  std::uint32_t c = crc ^ 0xffffffffu;
  for (const char ch : bytes) c = table[(c ^ static_cast<unsigned char>(ch)) & 0xffu] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

std::string format_npz(const Columns& table) {
  CAMOPT_ASSERT(!table.header.empty() && table.header.size() == table.values.size());
  CAMOPT_ASSERT(table.may_be_empty.empty() || table.may_be_empty.size() == table.values.size());
  const std::size_t rows = table.values.front().size();
  std::size_t total = kEndSize;
  for (std::size_t c = 0; c < table.values.size(); ++c) {
    CAMOPT_ASSERT_MSG(table.values[c].size() == rows, "format_npz: columns differ in length");
    check_column(table, c);
    total += kLocalSize + kCentralSize + 2 * (table.header[c].size() + 4) + npy_header(rows).size() + rows * 8;
  }
  if (total > kZipLimit || table.values.size() > 0xffff)
    throw InputError("--format npz: the table (" + std::to_string(table.values.size()) + " columns, " +
                     std::to_string(total) + " bytes) is beyond what a zip archive without zip64 holds (4 GiB, "
                     "65535 members); write it as CSV");
  std::string out, central;
  out.reserve(total);
  const std::string header = npy_header(rows);
  std::vector<double> written(rows);
  for (std::size_t c = 0; c < table.values.size(); ++c) {
    // the column as written: -0 as 0
    for (std::size_t r = 0; r < rows; ++r) written[r] = table.values[c][r] + 0.0;
    const std::string_view data(reinterpret_cast<const char*>(written.data()), rows * sizeof(double));
    const std::string name = table.header[c] + ".npy";
    const auto size = static_cast<std::uint32_t>(header.size() + data.size());
    // the crc of the header, continued over the data
    const std::uint32_t crc = crc32(data, crc32(header));
    const auto offset = static_cast<std::uint32_t>(out.size());
    put_member_header(out, false, name, crc, size, 0);
    out += header;
    out += data;
    put_member_header(central, true, name, crc, size, offset);
  }
  const auto central_offset = static_cast<std::uint32_t>(out.size());
  out += central;
  put32(out, kEndSignature);
  put16(out, 0);  // this disk
  put16(out, 0);  // the central directory's disk
  put16(out, static_cast<std::uint16_t>(table.values.size()));
  put16(out, static_cast<std::uint16_t>(table.values.size()));
  put32(out, static_cast<std::uint32_t>(central.size()));
  put32(out, central_offset);
  put16(out, 0);  // comment
  return out;
}

Columns parse_npz(std::string_view b, const std::string& file) {
  const std::size_t end = find_end_record(b, file);
  const std::size_t members = get16(b, end + 10);
  const std::size_t central_size = get32(b, end + 12), central_offset = get32(b, end + 16);
  if (members == 0) bad(file, "no arrays in it");
  if (central_offset + central_size > end) bad(file, "its central directory runs past its end record (truncated)");
  Columns table;
  for (std::size_t m = 0, at = central_offset; m < members; ++m) {
    if (at + kCentralSize > end || get32(b, at) != kCentralSignature)
      bad(file, "central directory entry " + std::to_string(m + 1) + " is damaged");
    const std::size_t name_size = get16(b, at + 28), extra = get16(b, at + 30), comment = get16(b, at + 32);
    const std::string name(b.substr(at + kCentralSize, std::min(name_size, end - at - kCentralSize)));
    if (get16(b, at + 10) != 0) bad(file, "member '" + name + "' is compressed (camopt writes them stored)");
    const std::uint32_t crc = get32(b, at + 16), size = get32(b, at + 24);
    const std::size_t local = get32(b, at + 42);
    if (local + kLocalSize > central_offset || get32(b, local) != kLocalSignature)
      bad(file, "member '" + name + "': no local header where the directory says");
    const std::size_t data = local + kLocalSize + get16(b, local + 26) + get16(b, local + 28);
    if (data + size > central_offset) bad(file, "member '" + name + "' runs past the archive's data (truncated)");
    const std::string_view npy = b.substr(data, size);
    if (crc32(npy) != crc) bad(file, "member '" + name + "': CRC-32 does not match (damaged)");
    if (name.size() < 5 || name.substr(name.size() - 4) != ".npy") bad(file, "member '" + name + "' is not a .npy");
    table.header.push_back(name.substr(0, name.size() - 4));
    table.values.push_back(parse_npy(npy, file, name));
    if (table.values.back().size() != table.values.front().size())
      bad(file, "member '" + name + "' has " + std::to_string(table.values.back().size()) + " values, '" +
                    table.header.front() + "' " + std::to_string(table.values.front().size()));
    at += kCentralSize + name_size + extra + comment;
  }
  // a NaN is an empty cell of the CSV
  for (const auto& column : table.values) {
    bool any_nan = false;
    for (double v : column) any_nan = any_nan || std::isnan(v);
    table.may_be_empty.push_back(any_nan);
  }
  return table;
}

Columns read_npz(const std::string& path) { return parse_npz(read_input_file(path, "npz file"), path); }

}  // namespace camopt::io
