// reading a result folder's files for the report: the CSVs (every column, from_chars, no
// iostreams) and the JSON files, each error naming the file and line or key.
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "camopt/core/error.hpp"
#include "camopt/core/printable.hpp"
#include "camopt/io/npz.hpp"
#include "camopt/io/table_layout.hpp"
#include "collect_support.hpp"

namespace camopt::report::detail {
namespace {

// the whole file, read into a string sized once; InputError naming it when it cannot be read
std::string read_text(const fs::path& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw InputError("cannot read '" + path.string() + "': " + std::strerror(errno));
  std::string text;
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  text.resize(ec ? 0 : static_cast<std::size_t>(size));
  text.resize(std::fread(text.data(), 1, text.size(), f));
  char buffer[1 << 16];  // anything beyond the size seen (a file that grew)
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) text.append(buffer, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw InputError("cannot read '" + path.string() + "': read error");
  return text;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// the next line of `rest` (without its newline), advancing `rest`
std::string_view next_line(std::string_view& rest) {
  const std::size_t end = rest.find('\n');
  const std::string_view line = rest.substr(0, end);
  rest.remove_prefix(end == std::string_view::npos ? rest.size() : end + 1);
  return line;
}

// one cell as a number: empty is NaN, anything but a whole number is an InputError
double parse_cell(std::string_view cell, const CsvData& csv, std::size_t column, int line) {
  cell = trim(cell);
  if (cell.empty()) return std::numeric_limits<double>::quiet_NaN();
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (ptr != cell.data() + cell.size() || ec != std::errc())
    throw InputError(csv.file + ":" + std::to_string(line) + ": column '" + csv.columns[column] + "': '" +
                     printable(cell) + "' is not a number");
  return value;
}

}  // namespace

const std::vector<double>* CsvData::find(std::string_view column) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == column) return &values[i];
  return nullptr;
}

const std::vector<double>& CsvData::at(std::string_view column) const {
  if (const auto* v = find(column)) return *v;
  std::string list;
  for (const auto& c : columns) list += (list.empty() ? "" : ", ") + c;
  throw InputError(file + ": no column '" + std::string(column) + "' (columns: " + list + ")");
}

CsvData read_csv(const fs::path& path) {
  CsvData csv;
  csv.file = path.string();
  const std::string text = read_text(path);
  std::string_view rest = text;
  // the header: names with units
  const std::string_view header = trim(next_line(rest));
  if (header.empty()) throw InputError(csv.file + ":1: no header line (an empty file)");
  for (std::string_view h = header;;) {
    const std::size_t comma = h.find(',');
    csv.columns.emplace_back(trim(h.substr(0, comma)));
    if (comma == std::string_view::npos) break;
    h.remove_prefix(comma + 1);
  }
  csv.values.resize(csv.columns.size());
  for (auto& v : csv.values) v.reserve(text.size() / (8 * csv.columns.size() + 1));
  // the rows: as many cells as the header, each a number or empty
  int line = 1;
  while (!rest.empty()) {
    const std::string_view row = trim(next_line(rest));
    ++line;
    if (row.empty()) continue;
    std::size_t column = 0, start = 0;
    for (;;) {
      const std::size_t comma = row.find(',', start);
      if (column >= csv.columns.size())
        throw InputError(csv.file + ":" + std::to_string(line) + ": more cells than the header's " +
                         std::to_string(csv.columns.size()));
      csv.values[column].push_back(parse_cell(row.substr(start, comma - start), csv, column, line));
      ++column;
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (column != csv.columns.size())
      throw InputError(csv.file + ":" + std::to_string(line) + ": " + std::to_string(column) + " cells, the header has " +
                       std::to_string(csv.columns.size()));
  }
  return csv;
}

bool Folder::has(const std::string& name) const {
  std::error_code ec;
  return fs::exists(path / name, ec);
}

namespace {

// a table read from an archive or a wide CSV, as the report reads a long CSV
CsvData csv_of(io::Columns table, const fs::path& file) {
  CsvData csv;
  csv.file = file.string();
  csv.columns = std::move(table.header);
  csv.values = std::move(table.values);
  return csv;
}

}  // namespace

CsvData Folder::csv(const std::string& name) const {
  // the table's file: the CSV, or the NumPy archive of the same stem (--format npz)
  std::string stored = name;
  if (!has(name) && has(fs::path(name).replace_extension(".npz").string()))
    stored = fs::path(name).replace_extension(".npz").string();
  // the run's table while the folder holds the file it committed
  const auto it = written ? written->find(stored) : WrittenTables::const_iterator{};
  if (!written || it == written->end() || io::file_id((path / stored).string()) != it->second.file) {
    if (stored != name) return csv_of(io::read_npz((path / stored).string()), path / stored);
    CsvData csv = read_csv(path / name);
    // a wide table (--format wide): its long table, as the report reads it
    for (const std::string& column : csv.columns)
      if (io::is_wide_column(column)) {
        io::Columns wide{std::move(csv.columns), std::move(csv.values), {}};
        return csv_of(io::long_table(wide, csv.file), path / name);
      }
    return csv;
  }
  const io::Columns& table = it->second.columns;
  CAMOPT_ASSERT(table.header.size() == table.values.size());
  CsvData csv;
  csv.file = (path / stored).string();
  csv.columns = table.header;
  csv.values = table.values;
  // the file's text of -0 is 0 (format_csv)
  for (auto& column : csv.values)
    for (double& v : column) v += 0.0;
  return csv;
}

nlohmann::json read_json(const fs::path& path) {
  const std::string text = read_text(path);
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw InputError(path.string() + ": not a JSON object as camopt writes it (a damaged or foreign file)");
  return j;
}

const nlohmann::json& member(const nlohmann::json& j, const std::string& key, const std::string& file,
                             const std::string& path) {
  const std::string full = path.empty() ? key : path + "." + key;
  if (!j.is_object()) throw InputError(file + ": '" + path + "' is not an object");
  const auto it = j.find(key);
  if (it == j.end()) throw InputError(file + ": no key '" + full + "'");
  return *it;
}

double number(const nlohmann::json& j, const std::string& key, const std::string& file, const std::string& path) {
  const nlohmann::json& v = member(j, key, file, path);
  if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v.is_number())
    throw InputError(file + ": key '" + (path.empty() ? key : path + "." + key) + "' is not a number");
  return v.get<double>();
}

}  // namespace camopt::report::detail
