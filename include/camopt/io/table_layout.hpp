#pragma once
// the layouts of a long result table (one row per key values and angle): the wide layout
// has one row per angle and one group of columns per key values, each column named
// <quantity with unit>@<key column>=<value>[@<key column>=<value>] (lift_mm@control_deg=4,
// contact_cam_roller_force_N@rpm=3000@control_deg=4)
#include <cstddef>
#include <string>

#include "camopt/io/csv.hpp"

namespace camopt::io {

// the wide table of a long one whose first `keys` columns are the keys and the next `angles`
// the angle (cam_deg, and crank_deg beside it), its rows grouped by consecutive equal keys,
// every group over the same angles (a bug otherwise: CAMOPT_ASSERT); the angle columns come
// first, once
Columns wide_table(const Columns& long_table, std::size_t keys, std::size_t angles = 1);

// the long table of a wide one (its angle columns first, the others named as above), the
// keys as columns in the order of the names; InputError "file: ..." for a column name that
// does not follow the layout or groups that do not carry the same quantities
Columns long_table(const Columns& wide_table, const std::string& file);

// a header name of the wide layout: its key part starts at '@'
bool is_wide_column(const std::string& name);

}  // namespace camopt::io
