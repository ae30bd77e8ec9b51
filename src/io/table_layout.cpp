// the wide layout of a long result table, and back
#include "camopt/io/table_layout.hpp"

#include <charconv>
#include <cstring>

#include "camopt/core/error.hpp"

namespace camopt::io {
namespace {

// shortest text that reads back to the same double (-0 as 0, as the CSV writes it)
std::string number_text(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value + 0.0).ptr);
}

// rows [begin, end) share the key values of one group
struct RowGroup {
  std::size_t begin = 0, end = 0;
};

std::vector<RowGroup> key_groups(const Columns& t, std::size_t keys) {
  std::vector<RowGroup> groups;
  const std::size_t rows = t.values.front().size();
  for (std::size_t r = 0; r < rows; ++r) {
    bool same = !groups.empty();
    for (std::size_t k = 0; k < keys && same; ++k) same = t.values[k][r] == t.values[k][groups.back().begin];
    if (same) groups.back().end = r + 1;
    else groups.push_back({r, r + 1});
  }
  return groups;
}

// a wide column's name split: the quantity and its keys (name, value)
struct WideName {
  std::string quantity;
  std::vector<std::pair<std::string, double>> keys;
};

WideName split_wide_name(const std::string& name, const std::string& file) {
  WideName w;
  std::size_t at = name.find('@');
  w.quantity = name.substr(0, at);
  while (at != std::string::npos) {
    const std::size_t next = name.find('@', at + 1);
    const std::string key = name.substr(at + 1, next == std::string::npos ? std::string::npos : next - at - 1);
    const std::size_t eq = key.find('=');
    double value = 0.0;
    const char* first = key.data() + (eq == std::string::npos ? key.size() : eq + 1);
    const auto parsed = std::from_chars(first, key.data() + key.size(), value);
    if (eq == std::string::npos || eq == 0 || parsed.ptr != key.data() + key.size() || parsed.ec != std::errc())
      throw InputError(file + ": column '" + name + "': '" + key +
                       "' is not <key column>=<number> (a wide table's columns are <quantity>@<key>=<value>)");
    w.keys.emplace_back(key.substr(0, eq), value);
    at = next;
  }
  return w;
}

}  // namespace

bool is_wide_column(const std::string& name) { return name.find('@') != std::string::npos; }

Columns wide_table(const Columns& t, std::size_t keys, std::size_t angles) {
  CAMOPT_ASSERT(t.header.size() == t.values.size() && t.header.size() > keys + angles && angles >= 1);
  const std::vector<RowGroup> groups = key_groups(t, keys);
  const std::size_t points = groups.front().end - groups.front().begin;
  Columns wide;
  // the angle columns, once: every group's angles are the same
  for (std::size_t a = keys; a < keys + angles; ++a) {
    wide.header.push_back(t.header[a]);
    wide.values.emplace_back(t.values[a].begin(), t.values[a].begin() + static_cast<std::ptrdiff_t>(points));
    wide.may_be_empty.push_back(false);
  }
  for (const RowGroup& g : groups) {
    CAMOPT_ASSERT_MSG(g.end - g.begin == points, "wide_table: groups of different lengths");
    for (std::size_t a = 0; a < angles; ++a)
      for (std::size_t i = 0; i < points; ++i)
        CAMOPT_ASSERT_MSG(t.values[keys + a][g.begin + i] == wide.values[a][i], "wide_table: groups over other angles");
    std::string suffix;
    for (std::size_t k = 0; k < keys; ++k) suffix += "@" + t.header[k] + "=" + number_text(t.values[k][g.begin]);
    for (std::size_t c = keys + angles; c < t.header.size(); ++c) {
      wide.header.push_back(t.header[c] + suffix);
      wide.values.emplace_back(t.values[c].begin() + static_cast<std::ptrdiff_t>(g.begin),
                               t.values[c].begin() + static_cast<std::ptrdiff_t>(g.end));
      wide.may_be_empty.push_back(!t.may_be_empty.empty() && t.may_be_empty[c]);
    }
  }
  return wide;
}

Columns long_table(const Columns& w, const std::string& file) {
  CAMOPT_ASSERT(w.header.size() == w.values.size() && !w.header.empty());
  // the angle columns: those before the first <quantity>@<key>=<value>
  std::size_t angles = 0;
  while (angles < w.header.size() && !is_wide_column(w.header[angles])) ++angles;
  if (angles == 0 || angles == w.header.size())
    throw InputError(file + ": a wide table starts with its angle columns, then <quantity>@<key>=<value> columns");
  // the groups: consecutive columns sharing their keys
  std::vector<WideName> names;
  for (std::size_t c = angles; c < w.header.size(); ++c) names.push_back(split_wide_name(w.header[c], file));
  std::vector<std::size_t> starts;  // column index in names of each group's first column
  for (std::size_t i = 0; i < names.size(); ++i)
    if (i == 0 || names[i].keys != names[i - 1].keys) starts.push_back(i);
  const std::size_t per_group = (starts.size() > 1 ? starts[1] : names.size());
  const std::size_t points = w.values[0].size();
  for (std::size_t g = 0; g < starts.size(); ++g)
    for (std::size_t q = 0; q < per_group; ++q) {
      const std::size_t i = starts[g] + q;
      const bool end = g + 1 < starts.size() ? i >= starts[g + 1] : i >= names.size();
      bool same = !end && names[i].quantity == names[q].quantity && names[i].keys.size() == names[0].keys.size();
      for (std::size_t k = 0; same && k < names[0].keys.size(); ++k)
        same = names[i].keys[k].first == names[0].keys[k].first;
      if (!same)
        throw InputError(file + ": column '" + (end ? w.header[angles + starts[g]] : w.header[angles + i]) +
                         "': the groups of a wide table carry the same quantities in the same order (the first: " +
                         std::to_string(per_group) + " from '" + w.header[angles] + "')");
    }
  if (starts.size() * per_group != names.size())
    throw InputError(file + ": " + std::to_string(names.size()) + " columns after the angle do not make groups of " +
                     std::to_string(per_group));
  Columns t;
  for (const auto& key : names[0].keys) t.header.push_back(key.first);
  for (std::size_t a = 0; a < angles; ++a) t.header.push_back(w.header[a]);
  for (std::size_t q = 0; q < per_group; ++q) t.header.push_back(names[q].quantity);
  t.values.resize(t.header.size());
  const std::size_t keys = names[0].keys.size();
  for (std::size_t g = 0; g < starts.size(); ++g) {
    for (std::size_t k = 0; k < keys; ++k) t.values[k].insert(t.values[k].end(), points, names[starts[g]].keys[k].second);
    for (std::size_t a = 0; a < angles; ++a)
      t.values[keys + a].insert(t.values[keys + a].end(), w.values[a].begin(), w.values[a].end());
    for (std::size_t q = 0; q < per_group; ++q) {
      const auto& column = w.values[angles + starts[g] + q];
      t.values[keys + angles + q].insert(t.values[keys + angles + q].end(), column.begin(), column.end());
    }
  }
  return t;
}

}  // namespace camopt::io
