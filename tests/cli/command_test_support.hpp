#pragma once
// helpers of the end-to-end command tests: the test data folders, CLI11 help entries and
// their units, CSV rows and column units
#include <algorithm>
#include <cctype>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_support.hpp"

namespace camopt::test::commands {


inline const std::vector<std::string> kSubcommands = {"validate", "kinematics", "synthesize", "lift", "optimize", "dynamics"};

// small valid inputs of our own (tests/data/cli/)
inline fs::path cli_data(const std::string& name) { return source_dir() / "tests" / "data" / "cli" / name; }
inline fs::path bundled_design(const std::string& name) { return source_dir() / "designs" / name; }

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// an output directory that was never created, or holds no files at all
inline bool no_output(const fs::path& dir) { return files_under(dir).empty(); }

// one entry of a CLI11 help text: the name column and its description (continuation lines
// joined), e.g. "--lift FLOAT   maximum lift [mm]"
struct HelpEntry {
  std::vector<std::string> names;  // "-q", "--quiet"
  std::string type;                // "FLOAT", "INT:POSITIVE", "TEXT", ... ("" for flags)
  std::string text;                // the whole entry
};

inline std::vector<HelpEntry> help_entries(const std::string& help) {
  std::vector<HelpEntry> entries;
  bool in_entry = false;
  for (const auto& line : split_lines(help)) {
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos || first == 0) {
      in_entry = false;  // blank line or section header
    } else if (first == 2) {
      HelpEntry e;
      e.text = line;
      std::istringstream tokens(line);
      std::string name_column, type;
      tokens >> name_column >> type;
      std::string::size_type start = 0, comma;
      while ((comma = name_column.find(',', start)) != std::string::npos) {
        e.names.push_back(name_column.substr(start, comma - start));
        start = comma + 1;
      }
      e.names.push_back(name_column.substr(start));
      e.type = type;
      entries.push_back(e);
      in_entry = true;
    } else if (in_entry) {
      entries.back().text += " " + line.substr(first);
    }
  }
  return entries;
}

inline const HelpEntry* find_option(const std::vector<HelpEntry>& entries, const std::string& name) {
  for (const auto& e : entries)
    for (const auto& n : e.names)
      if (n == name) return &e;
  return nullptr;
}

inline bool is_numeric_type(const std::string& type) {
  static const std::regex numeric(R"(^(INT|UINT|FLOAT|DOUBLE|NUMBER)(:.*)?$)");
  return std::regex_match(type, numeric);
}

// "[...]" somewhere in the entry, and (if given) one holding `unit` as a word
inline bool has_bracketed_unit(const std::string& text, const std::string& unit = "") {
  const std::regex any(R"(\[[^\]]+\])");
  if (unit.empty()) return std::regex_search(text, any);
  return std::regex_search(text, std::regex(R"(\[[^\]]*\b)" + unit + R"(\b[^\]]*\])"));
}

// a CSV column name ends in a unit: _deg, _mm, _mm_per_deg2, _rad_per_deg, _per_mm, _N, ...
inline bool has_unit_suffix(const std::string& column) {
  static const std::string unit = R"((deg|rad|mm|m|um|s|ms|N|Nm|Nmm|MPa|GPa|kg|kg_mm2|rpm|J|W|Hz|pct|1)[23]?)";
  static const std::regex suffix("(_" + unit + "(_per_" + unit + ")*|(_per_" + unit + ")+)$");
  return std::regex_search(column, suffix);
}

inline std::vector<std::string> split_csv_row(const std::string& line) {
  std::vector<std::string> cells;
  std::string::size_type start = 0, comma;
  while ((comma = line.find(',', start)) != std::string::npos) {
    cells.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
  cells.push_back(line.substr(start));
  for (auto& c : cells) {
    const auto b = c.find_first_not_of(" \t"), e = c.find_last_not_of(" \t");
    c = b == std::string::npos ? std::string() : c.substr(b, e - b + 1);
  }
  return cells;
}

inline std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}


}  // namespace camopt::test::commands
