#pragma once
// CSV tables: lift tables, profiles, spring/gas tables. Header with units, '#' comment
// lines, comma / semicolon / whitespace delimiters. Errors name file:line.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace camopt::io {

struct CsvTable {
  std::string file;                        // for messages
  std::vector<std::string> columns;        // header names, trimmed, as written
  std::vector<std::vector<double>> values; // values[column][row]
  std::vector<int> lines;                  // file line of each data row (1-based)

  std::size_t rows() const { return lines.size(); }
  std::optional<std::size_t> find(std::string_view column) const;  // case-insensitive
  // the column, or InputError "file: no column 'name' (columns: ...)"
  const std::vector<double>& column(std::string_view column) const;
  // the one column whose name is one of `names`; InputError listing them when there is none,
  // or naming both when there are several (which one was meant is not for us to guess)
  std::size_t require_one_of(const std::vector<std::string>& names, std::string_view what) const;
};

// parse text; every cell must be a finite number (NaN/Inf rejected) and every row must
// have as many cells as the header. Throws InputError "file:line: ...".
CsvTable parse_csv(std::string_view text, const std::string& file_name);
CsvTable read_csv(const std::string& path);

// throws InputError "file:line: column 'c' value v is not greater than previous value p"
void require_strictly_increasing(const CsvTable& table, std::size_t column);

enum class AngleBasis { cam, crank };
const char* to_string(AngleBasis basis);

// a table of one quantity against cam or crank angle; the basis is always explicit:
// the angle column must be named cam_deg / cam_angle_deg or crank_deg / crank_angle_deg.
struct AngleTable {
  std::string file;
  AngleBasis basis = AngleBasis::cam;
  std::string angle_column, value_column;
  std::vector<double> angle_deg;  // as written (strictly increasing, checked)
  std::vector<double> value;
  std::vector<int> lines;
};

// value_names: accepted names of the value column, e.g. {"lift_mm","valve_lift_mm"}
AngleTable read_angle_table(const CsvTable& table, const std::vector<std::string>& value_names);

// check a table spans one full cycle [period_deg] (last - first >= period - step tolerance);
// throws InputError naming the file and the covered range when it does not
void require_full_cycle(const AngleTable& table, double period_deg);

// csv text of columns (header names must carry units); every number is the shortest text
// that reads back to the same double (std::to_chars, no locale, written straight into one
// growing buffer), so a table written and read back is bit-for-bit the same; -0 is written 0. A non-finite value is a kernel bug and throws
// std::logic_error naming the column and row
std::string format_csv(const std::vector<std::string>& header, const std::vector<std::vector<double>>& columns);
// the same, where a NaN in a column flagged in may_be_empty (one flag per column) is written
// as an empty cell: a quantity that does not exist at that row, such as the film thickness of
// an open contact. Any other non-finite value still throws.
// threads: rows formatted in chunks on up to that many threads (the text is the same)
std::string format_csv(const std::vector<std::string>& header, const std::vector<std::vector<double>>& columns,
                       const std::vector<bool>& may_be_empty, int threads = 1);

// a result table held in memory: header names with units, one vector per column, and the
// columns whose NaN is an empty cell (none when may_be_empty is empty)
struct Columns {
  std::vector<std::string> header;
  std::vector<std::vector<double>> values;
  std::vector<bool> may_be_empty;
};
// format_csv of the table, with its may_be_empty
std::string format_csv(const Columns& table, int threads = 1);

// write columns (header names must carry units) to `path` atomically
void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns);

}  // namespace camopt::io
