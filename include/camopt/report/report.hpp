#pragma once
// the interactive report of one run: collect() reads a result folder written by a camopt
// subcommand (or a lift table) into a ReportData, render_html() makes the self-contained
// page (docs/report.md), write_report() does both and writes it atomically.
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "camopt/io/atomic_file.hpp"
#include "camopt/io/csv.hpp"
#include "camopt/report/report_data.hpp"

namespace camopt::report {

// the run's plots and tables, from the files in `source`: a result folder of kinematics,
// synthesize, optimize or dynamics (its summary.json / report.json say which), or a lift
// table written by `camopt lift` (a CSV file). Series are decimated for display
// (decimate()). InputError naming the file, line or key for a folder that holds no
// recognisable result, a malformed CSV or a missing JSON key.
// `written`: the CSV tables of the folder that the run writing it holds in memory, by file
// name, each with the file it committed; a table is taken instead of reading its file back
// while the folder still holds that file (another run may have replaced the set since). The
// file is the table's shortest round-trip text, so the page is the same byte for byte (a
// negative zero is written 0, an empty cell is a NaN, and so they are taken).
struct WrittenTable {
  io::Columns columns;
  io::FileId file;
};
using WrittenTables = std::map<std::string, WrittenTable>;
ReportData collect(const std::filesystem::path& source, const WrittenTables& written = {});

// report.html: the page template with the assets inlined and the data as JSON
// (docs/report.md, "Data format")
std::string render_html(const ReportData& data);

// where the report of `source` goes: <folder>/report.html, or <stem>.report.html beside a
// lift table
std::filesystem::path report_path(const std::filesystem::path& source);

// collect + render + an atomic write to report_path(source), which it returns; on failure
// nothing is written (InputError naming what could not be read or written)
std::filesystem::path write_report(const std::filesystem::path& source);

// ---- display decimation -------------------------------------------------------------------
// a series of n > max_points points is cut into B = (max_points - 2) / 2 buckets of
// consecutive points, bucket b holding the indices [b n / B, (b + 1) n / B); each bucket keeps
// the index of its smallest and of its largest y (the first of equal values; NaN is never a
// bucket's extreme unless the bucket is all NaN), and the first and last points are always
// kept: at most max_points indices, increasing. n <= max_points: every index.
std::vector<std::size_t> decimation_indices(const std::vector<double>& y, std::size_t max_points);

// every series of every line plot longer than kMaxDisplayPoints decimated by its y (a series
// on the plot's shared x gets its own x then); profile series by their distance from the
// origin; heatmaps are left as they are
void decimate(ReportData& data, std::size_t max_points = kMaxDisplayPoints);

// ---- the data format's pieces (exposed for the tests) ---------------------------------------
// the base64 of the values as little-endian IEEE float32
std::string base64_float32(const std::vector<double>& values);
// ReportData as the page's JSON, with every "</" written "<\/"
std::string to_json(const ReportData& data);

}  // namespace camopt::report
