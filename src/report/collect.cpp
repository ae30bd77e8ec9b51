// collect(): which run wrote the folder, its collector, then the display decimation.
#include <algorithm>
#include <cmath>
#include <system_error>

#include "camopt/core/error.hpp"
#include "camopt/report/report.hpp"
#include "collect_support.hpp"

namespace camopt::report {
namespace {

namespace fs = std::filesystem;
using detail::read_json;

// the newer of two files that exist (a folder written by two commands: the later run's)
bool newer(const fs::path& a, const fs::path& b) {
  std::error_code ec_a, ec_b;
  const auto ta = fs::last_write_time(a, ec_a), tb = fs::last_write_time(b, ec_b);
  return !ec_a && (ec_b || ta >= tb);
}

// a folder's summary.json: kinematics or one of the dynamics models
void collect_summary(ReportData& data, const detail::Folder& dir) {
  const nlohmann::json summary = read_json(dir / "summary.json");
  const std::string file = (dir / "summary.json").string();
  const auto model = summary.find("model");
  if (model == summary.end()) {
    data.command = "kinematics";
    detail::collect_kinematics(data, dir, summary);
  } else if (*model == "rigid") {
    data.command = "dynamics rigid";
    detail::collect_rigid(data, dir, summary);
  } else if (*model == "flexible") {
    data.command = "dynamics flexible";
    detail::collect_flexible(data, dir, summary);
  } else if (*model == "modes") {
    data.command = "dynamics modes";
    detail::collect_modes(data, dir, summary);
  } else {
    throw InputError(file + ": key 'model': '" + model->dump() + "' is none of rigid, flexible, modes");
  }
}

// a folder's report.json: optimize (it names a constraint set) or synthesize
void collect_design_report(ReportData& data, const detail::Folder& dir) {
  const nlohmann::json report = read_json(dir / "report.json");
  if (report.contains("constraint_set")) {
    data.command = "optimize";
    detail::collect_optimize(data, dir, report);
  } else {
    data.command = "synthesize";
    detail::collect_synthesize(data, dir, report);
  }
}

// the source as the report names it: lexically normal, no trailing separator
std::string source_name(const fs::path& source) {
  std::string s = source.lexically_normal().string();
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return s;
}

// the bucket's extreme indices by `less` over finite-or-inf values, NaN skipped
std::pair<std::size_t, std::size_t> bucket_extremes(const std::vector<double>& y, std::size_t begin, std::size_t end) {
  std::size_t lo = end, hi = end;
  for (std::size_t i = begin; i < end; ++i) {
    if (std::isnan(y[i])) continue;
    if (lo == end || y[i] < y[lo]) lo = i;
    if (hi == end || y[i] > y[hi]) hi = i;
  }
  if (lo == end) lo = hi = begin;  // all NaN
  return {std::min(lo, hi), std::max(lo, hi)};
}

// the values at the kept indices
std::vector<double> pick(const std::vector<double>& v, const std::vector<std::size_t>& keep) {
  std::vector<double> out;
  out.reserve(keep.size());
  for (std::size_t i : keep) out.push_back(v[i]);
  return out;
}

// one series decimated: by y on a line plot, by the distance from the origin on a profile
void decimate_series(Series& s, const std::vector<double>& shared_x, PlotKind kind, std::size_t max_points) {
  const std::vector<double>& x = s.x.empty() ? shared_x : s.x;
  if (s.y.size() <= max_points) return;
  std::vector<double> by = s.y;
  if (kind == PlotKind::profile)
    for (std::size_t i = 0; i < by.size(); ++i) by[i] = std::hypot(x[i], s.y[i]);
  const std::vector<std::size_t> keep = decimation_indices(by, max_points);
  s.x = pick(x, keep);
  s.y = pick(s.y, keep);
  if (!s.color.empty()) s.color = pick(s.color, keep);
}

}  // namespace

std::vector<std::size_t> decimation_indices(const std::vector<double>& y, std::size_t max_points) {
  const std::size_t n = y.size();
  std::vector<std::size_t> keep;
  if (n <= max_points) {
    keep.resize(n);
    for (std::size_t i = 0; i < n; ++i) keep[i] = i;
    return keep;
  }
  CAMOPT_ASSERT_MSG(max_points >= 4, "decimation_indices: max_points below 4");
  const std::size_t buckets = (max_points - 2) / 2;
  keep.push_back(0);
  for (std::size_t b = 0; b < buckets; ++b) {
    const auto [first, second] = bucket_extremes(y, b * n / buckets, (b + 1) * n / buckets);
    for (std::size_t i : {first, second})
      if (i != keep.back()) keep.push_back(i);
  }
  if (keep.back() != n - 1) keep.push_back(n - 1);
  return keep;
}

void decimate(ReportData& data, std::size_t max_points) {
  for (Plot& plot : data.plots) {
    if (plot.kind == PlotKind::heatmap) continue;
    for (Series& s : plot.series) decimate_series(s, plot.x_values, plot.kind, max_points);
    // the shared x is dropped once no series reads it
    if (std::all_of(plot.series.begin(), plot.series.end(), [](const Series& s) { return !s.x.empty(); }))
      plot.x_values.clear();
  }
}

ReportData collect(const fs::path& source, const WrittenTables& written) {
  ReportData data;
  data.source_dir = source_name(source);
  std::error_code ec;
  const auto status = fs::status(source, ec);
  if (!fs::exists(status)) throw InputError("'" + source.string() + "': no such folder or file");
  // which run wrote it
  if (fs::is_regular_file(status)) {
    data.command = "lift";
    detail::collect_lift_table(data, source);
  } else {
    const bool summary = fs::exists(source / "summary.json", ec), report = fs::exists(source / "report.json", ec);
    if (summary && (!report || newer(source / "summary.json", source / "report.json")))
      collect_summary(data, {source, &written});
    else if (report)
      collect_design_report(data, {source, &written});
    else
      throw InputError("'" + source.string() +
                       "': no camopt result in it (summary.json of kinematics or dynamics, or report.json of "
                       "synthesize or optimize)");
  }
  // the page's copy of the series: peaks kept, at most kMaxDisplayPoints points each
  decimate(data);
  return data;
}

}  // namespace camopt::report
