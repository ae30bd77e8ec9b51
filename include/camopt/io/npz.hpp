#pragma once
// NumPy .npz archives of a result table: an uncompressed zip of one .npy array per column
// (little-endian float64, one dimension), named by the column's header with its units, so
// that numpy.load reads it with no other package. Written and read bit for bit: a value read
// back is the double written (a NaN is an empty cell of the CSV, -0 is written as 0, as the
// CSV writes it).
#include <cstdint>
#include <string>
#include <string_view>

#include "camopt/io/csv.hpp"

namespace camopt::io {

// the archive's bytes: one member <header name>.npy per column, in the table's order. A
// non-finite value is a bug (std::logic_error naming the column and row) unless the column
// may be empty and the value is a NaN, as format_csv
std::string format_npz(const Columns& table);

// the table of an archive as format_npz writes it (file names it in messages). InputError
// "file: ..." naming what is wrong when the bytes are not such an archive: truncated, a
// member compressed or not float64 one-dimensional, columns of different lengths, a CRC
// that does not match
Columns parse_npz(std::string_view bytes, const std::string& file);
// the file read and parsed
Columns read_npz(const std::string& path);

// CRC-32 (ISO-HDLC, the zip format's) of bytes; crc: the CRC of the bytes before them
std::uint32_t crc32(std::string_view bytes, std::uint32_t crc = 0);

}  // namespace camopt::io
