#include "camopt/io/csv.hpp"

#include "camopt/io/input_file.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "camopt/core/error.hpp"
#include "camopt/core/parallel.hpp"
#include "camopt/core/printable.hpp"
#include "camopt/io/atomic_file.hpp"

namespace camopt::io {
namespace {

// accepted angle column names per basis (compared case-insensitively)
const std::vector<std::string> kCamAngleNames = {"cam_deg", "cam_angle_deg"};
const std::vector<std::string> kCrankAngleNames = {"crank_deg", "crank_angle_deg"};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
  return s;
}

std::string to_lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool iequals(std::string_view a, std::string_view b) { return to_lower(a) == to_lower(b); }

std::string join(const std::vector<std::string>& items, std::string_view separator = ", ") {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += separator;
    out += items[i];
  }
  return out;
}

// shortest text that reads back to the same double
std::string format_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string where(const std::string& file, int line) { return file + ":" + std::to_string(line); }

enum class ParseOutcome { ok, not_a_number, not_finite };

// the whole cell must be one finite number; a leading '+' is accepted
ParseOutcome parse_number(std::string_view cell, double& value) {
  std::string_view digits = cell;
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-' && digits[1] != '+')
    digits.remove_prefix(1);
  const char* first = digits.data();
  const char* last = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(first, last, value);
  if (ptr != last || (ec != std::errc() && ec != std::errc::result_out_of_range))
    return ParseOutcome::not_a_number;
  if (ec == std::errc::result_out_of_range) {
    // overflow is not finite; underflow reads as the nearest tiny value
    value = std::strtod(std::string(digits).c_str(), nullptr);
  }
  return std::isfinite(value) ? ParseOutcome::ok : ParseOutcome::not_finite;
}

// delimiter of the header line: ',' then ';' then runs of whitespace (' ')
char detect_delimiter(std::string_view header) {
  if (header.find(',') != std::string_view::npos) return ',';
  if (header.find(';') != std::string_view::npos) return ';';
  return ' ';
}

// the cells of a line into `cells` (its storage reused from row to row)
void split_cells(std::string_view line, char delimiter, std::vector<std::string_view>& cells) {
  cells.clear();
  if (delimiter == ' ') {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_blank(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_blank(line[i])) ++i;
      if (i > start) cells.push_back(line.substr(start, i - start));
    }
    return;
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(delimiter, start);
    cells.push_back(trim(line.substr(start, end == std::string_view::npos ? end : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
}

// the line without its trailing comment, CR and surrounding whitespace
std::string_view content_of(std::string_view line) {
  const std::size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  return trim(line);
}

}  // namespace

std::optional<std::size_t> CsvTable::find(std::string_view name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (iequals(columns[i], name)) return i;
  return std::nullopt;
}

const std::vector<double>& CsvTable::column(std::string_view name) const {
  const auto index = find(name);
  if (!index)
    throw InputError(file + ": no column '" + std::string(name) + "' (columns: " + join(columns) + ")");
  return values[*index];
}

std::size_t CsvTable::require_one_of(const std::vector<std::string>& names, std::string_view what) const {
  std::vector<std::size_t> found;
  for (std::size_t i = 0; i < columns.size(); ++i)
    for (const auto& name : names)
      if (iequals(columns[i], name)) found.push_back(i);
  if (found.size() > 1)
    throw InputError(file + ": more than one " + std::string(what) + " column ('" + columns[found[0]] + "', '" +
                     columns[found[1]] + "'); keep exactly one of " + join(names));
  if (found.size() == 1) return found.front();
  throw InputError(file + ": no " + std::string(what) + " column: expected one of " + join(names) +
                   " (columns: " + join(columns) + ")");
}

CsvTable parse_csv(std::string_view text, const std::string& file_name) {
  CsvTable table;
  table.file = file_name;

  // utf-8 byte order mark
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  if (text.find_first_not_of(" \t\r\n\v\f") == std::string_view::npos)
    throw InputError(file_name + ": empty file (a header line naming the columns is required)");

  char delimiter = ',';
  std::vector<std::string_view> cells;  // one row's, reused
  bool have_header = false;
  int line_number = 0;
  std::size_t position = 0;
  while (position < text.size()) {
    const std::size_t end = std::min(text.find('\n', position), text.size());
    const std::string_view line = content_of(text.substr(position, end - position));
    position = end + 1;
    ++line_number;
    if (line.empty()) continue;

    if (!have_header) {
      delimiter = detect_delimiter(line);
      std::vector<std::string_view> names;
      split_cells(line, delimiter, names);
      bool all_numeric = true;
      for (std::size_t i = 0; i < names.size(); ++i) {
        if (names[i].empty())
          throw InputError(where(file_name, line_number) + ": header column " + std::to_string(i + 1) +
                           " has no name");
        for (std::size_t j = 0; j < i; ++j)
          if (iequals(names[i], names[j]))
            throw InputError(where(file_name, line_number) + ": duplicate column name '" +
                             printable(names[i]) + "' (columns " + std::to_string(j + 1) + " and " +
                             std::to_string(i + 1) + ")");
        double ignored = 0.0;
        if (parse_number(names[i], ignored) == ParseOutcome::not_a_number) all_numeric = false;
      }
      if (all_numeric)
        throw InputError(where(file_name, line_number) + ": expected a header line naming the columns, found '" +
                         printable(line) + "'");
      for (const auto& name : names) table.columns.emplace_back(name);
      table.values.resize(table.columns.size());
      // room for every line left (no regrowth of the columns)
      const auto lines_left = static_cast<std::size_t>(std::count(text.begin() + static_cast<std::ptrdiff_t>(std::min(position, text.size())), text.end(), '\n')) + 1;
      for (auto& column : table.values) column.reserve(lines_left);
      table.lines.reserve(lines_left);
      have_header = true;
      continue;
    }

    split_cells(line, delimiter, cells);
    if (cells.size() != table.columns.size())
      throw InputError(where(file_name, line_number) + ": expected " + std::to_string(table.columns.size()) +
                       " cells (columns: " + join(table.columns) + "), found " + std::to_string(cells.size()));
    for (std::size_t c = 0; c < cells.size(); ++c) {
      // the location text is built only for an error
      const auto prefix = [&] { return where(file_name, line_number) + ": column '" + table.columns[c] + "'"; };
      if (cells[c].empty()) throw InputError(prefix() + " is empty");
      double value = 0.0;
      switch (parse_number(cells[c], value)) {
        case ParseOutcome::ok: break;
        case ParseOutcome::not_a_number:
          throw InputError(prefix() + " value '" + printable(cells[c]) + "' is not a number");
        case ParseOutcome::not_finite:
          throw InputError(prefix() + " value '" + printable(cells[c]) + "' is not finite");
      }
      table.values[c].push_back(value);
    }
    table.lines.push_back(line_number);
  }

  if (!have_header)
    throw InputError(file_name + ": no header line (the file holds only comments and blank lines)");
  if (table.rows() == 0)
    throw InputError(file_name + ": no data rows after the header (columns: " + join(table.columns) + ")");
  return table;
}

CsvTable read_csv(const std::string& path) { return parse_csv(read_input_file(path, "csv file"), path); }

void require_strictly_increasing(const CsvTable& table, std::size_t column) {
  CAMOPT_ASSERT(column < table.columns.size());
  const auto& values = table.values[column];
  for (std::size_t row = 1; row < values.size(); ++row) {
    if (values[row] > values[row - 1]) continue;
    throw InputError(where(table.file, table.lines[row]) + ": column '" + table.columns[column] + "' value " +
                     format_number(values[row]) + " is not greater than the previous value " +
                     format_number(values[row - 1]) + " (line " + std::to_string(table.lines[row - 1]) +
                     "); angles must be strictly increasing");
  }
}

const char* to_string(AngleBasis basis) {
  switch (basis) {
    case AngleBasis::cam: return "cam";
    case AngleBasis::crank: return "crank";
  }
  return "unknown";
}

AngleTable read_angle_table(const CsvTable& table, const std::vector<std::string>& value_names) {
  const std::string accepted = join(kCamAngleNames) + " (cam angle) or " + join(kCrankAngleNames) +
                               " (crank angle)";

  // exactly one column naming its basis
  std::vector<std::pair<std::size_t, AngleBasis>> angle_columns;
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    for (const auto& name : kCamAngleNames)
      if (iequals(table.columns[i], name)) angle_columns.emplace_back(i, AngleBasis::cam);
    for (const auto& name : kCrankAngleNames)
      if (iequals(table.columns[i], name)) angle_columns.emplace_back(i, AngleBasis::crank);
  }
  if (angle_columns.size() > 1)
    throw InputError(table.file + ": more than one angle column ('" + table.columns[angle_columns[0].first] +
                     "', '" + table.columns[angle_columns[1].first] + "'); keep exactly one of " + accepted);
  if (angle_columns.empty()) {
    // a generic angle column: the basis cannot be guessed
    for (const auto& name : table.columns) {
      const std::string lower = to_lower(name);
      if (lower.find("angle") != std::string::npos || lower.find("deg") != std::string::npos ||
          lower == "theta" || lower == "phi")
        throw InputError(table.file + ": column '" + name +
                         "' does not say whether it is cam or crank angle; the angle basis must be "
                         "explicit: name the column one of " + accepted);
    }
    throw InputError(table.file + ": no angle column: expected one of " + accepted + " (columns: " +
                     join(table.columns) + ")");
  }

  const auto [angle_index, basis] = angle_columns.front();
  const std::size_t value_index = table.require_one_of(value_names, "value");
  if (table.rows() < 2)
    throw InputError(table.file + ": an angle table needs at least 2 rows, found " +
                     std::to_string(table.rows()));
  require_strictly_increasing(table, angle_index);

  AngleTable out;
  out.file = table.file;
  out.basis = basis;
  out.angle_column = table.columns[angle_index];
  out.value_column = table.columns[value_index];
  out.angle_deg = table.values[angle_index];
  out.value = table.values[value_index];
  out.lines = table.lines;
  return out;
}

void require_full_cycle(const AngleTable& table, double period_deg) {
  CAMOPT_ASSERT(period_deg > 0.0);
  CAMOPT_ASSERT(table.angle_deg.size() >= 2);
  const double first = table.angle_deg.front();
  const double last = table.angle_deg.back();
  const double span = last - first;
  double max_step = 0.0;
  for (std::size_t i = 1; i < table.angle_deg.size(); ++i)
    max_step = std::max(max_step, table.angle_deg[i] - table.angle_deg[i - 1]);

  const std::string basis = to_string(table.basis);
  const std::string covered = format_number(first) + " to " + format_number(last) + " deg " + basis +
                              " (span " + format_number(span) + " deg)";
  const std::string period = format_number(period_deg) + " deg " + basis;
  // the closing step wraps from last to first + period
  if (span + max_step < period_deg * (1.0 - 1e-9))
    throw InputError(table.file + ": table covers " + covered + ", less than the full cycle of " + period +
                     " required");
  if (span > period_deg * (1.0 + 1e-9))
    throw InputError(table.file + ": table covers " + covered + ", more than one cycle of " + period +
                     "; give exactly one cycle");
}

namespace {

// the longest shortest-round-trip text of a double: -2.2250738585072014e-308
constexpr std::size_t kMaxNumberChars = 24;
// rows formatted per task of a parallel format
constexpr std::size_t kRowsPerChunk = 4096;

// a non-finite value in a result is a kernel bug, not bad input
[[noreturn]] void throw_non_finite(const std::vector<std::string>& header, std::size_t column, std::size_t row) {
  throw std::logic_error("write_csv: non-finite value in column '" + header[column] + "' row " +
                         std::to_string(row + 1));
}

// rows [first, last) of the columns as CSV lines, appended to `out`: every number written
// by std::to_chars straight into the one buffer (grown by doubling), -0 as 0, a NaN of a
// column that may be empty as nothing; any other non-finite value throws (throw_non_finite)
void append_rows(const std::vector<std::string>& header, const std::vector<std::vector<double>>& columns,
                 const std::vector<bool>& may_be_empty, std::size_t first, std::size_t last, std::string& out) {
  const std::size_t row_max = columns.size() * (kMaxNumberChars + 1) + 1;
  std::size_t used = out.size();
  out.resize(used + (last - first) * columns.size() * 12 + row_max);
  for (std::size_t r = first; r < last; ++r) {
    if (used + row_max > out.size()) out.resize(std::max(2 * out.size(), used + row_max));
    char* p = out.data() + used;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c > 0) *p++ = ',';
      const double v = columns[c][r];
      // + 0.0 turns a negative zero (e.g. a lift of -0 at rest) into 0
      if (std::isfinite(v)) p = std::to_chars(p, p + kMaxNumberChars, v + 0.0).ptr;
      else if (!(may_be_empty[c] && std::isnan(v))) throw_non_finite(header, c, r);
    }
    *p++ = '\n';
    used = static_cast<std::size_t>(p - out.data());
  }
  out.resize(used);
}

}  // namespace

std::string format_csv(const std::vector<std::string>& header, const std::vector<std::vector<double>>& columns) {
  return format_csv(header, columns, std::vector<bool>(columns.size(), false));
}

std::string format_csv(const std::vector<std::string>& header, const std::vector<std::vector<double>>& columns,
                       const std::vector<bool>& may_be_empty, int threads) {
  CAMOPT_ASSERT(!header.empty());
  CAMOPT_ASSERT(header.size() == columns.size());
  CAMOPT_ASSERT(may_be_empty.size() == columns.size());
  for (const auto& name : header)
    CAMOPT_ASSERT_MSG(!name.empty() && name.find_first_of(",#\r\n") == std::string::npos,
                      "write_csv: header names must be non-empty without ',', '#' or newlines");
  const std::size_t rows = columns.front().size();
  for (const auto& column : columns) CAMOPT_ASSERT_MSG(column.size() == rows, "write_csv: columns differ in length");

  std::string text = join(header, ",") + "\n";
  const std::size_t chunks = (rows + kRowsPerChunk - 1) / kRowsPerChunk;
  if (threads <= 1 || chunks <= 1) {
    append_rows(header, columns, may_be_empty, 0, rows, text);
    return text;
  }
  // chunks of rows formatted on the threads, then joined in order
  std::vector<std::string> parts(chunks);
  parallel_for(chunks, threads, [&](std::size_t k) {
    append_rows(header, columns, may_be_empty, k * kRowsPerChunk, std::min(rows, (k + 1) * kRowsPerChunk), parts[k]);
  });
  std::size_t size = text.size();
  for (const auto& part : parts) size += part.size();
  text.reserve(size);
  for (const auto& part : parts) text += part;
  return text;
}

std::string format_csv(const Columns& table, int threads) {
  if (table.may_be_empty.empty())
    return format_csv(table.header, table.values, std::vector<bool>(table.values.size(), false), threads);
  return format_csv(table.header, table.values, table.may_be_empty, threads);
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns) {
  write_text_atomic(path, format_csv(header, columns));
}

}  // namespace camopt::io
