// the data format's pieces: base64 float32, the JSON's escaping inside the page, the
// template's placeholders, and the display decimation against a bucket check written here.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "report/report_support.hpp"

namespace camopt::test {
namespace {

using report::ReportData;

TEST_CASE("report: base64 float32 of known values") {
  // 1.0f = 0x3F800000, bytes 00 00 80 3F (little-endian): base64 "AACAPw=="
  CHECK(report::base64_float32({1.0}) == "AACAPw==");
  // -2.0f = 0xC0000000 and 0.5f = 0x3F000000: bytes 00 00 00 C0 00 00 00 3F
  CHECK(report::base64_float32({-2.0, 0.5}) == "AAAAwAAAAD8=");
  CHECK(report::base64_float32({}).empty());
  // three values: 12 bytes, no padding; decoded back to the float32 of each value
  const std::vector<double> values = {0.1, -123456.789, 3.0e-20, std::numeric_limits<double>::quiet_NaN(), 8.4};
  const std::vector<float> back = decode_float32(report::base64_float32(values));
  REQUIRE(back.size() == values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    INFO("value " << i);
    if (std::isnan(values[i]))
      CHECK(std::isnan(back[i]));
    else
      CHECK(back[i] == static_cast<float>(values[i]));
  }
}

TEST_CASE("report: the JSON writes every closing tag as <\\/ and reads back to the text") {
  ReportData d;
  d.command = "kinematics";
  d.title = "cam </script><!-- \"quoted\" \\ end";
  d.notes = {"a note with </style> and a\nnewline"};
  d.facts = {{"key </b>", "value"}};
  const std::string json = report::to_json(d);
  CHECK(json.find("</") == std::string::npos);
  CHECK(json.find("<!--") == std::string::npos);
  CHECK(json.find("<\\/script>") != std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(json);
  CHECK(j["title"] == d.title);
  CHECK(j["notes"][0] == d.notes[0]);
  CHECK(j["facts"][0]["key"] == "key </b>");
  CHECK(j["format"] == "camopt-report");
  CHECK(j["version"] == 1);
  CHECK(j["scene"].is_null());
  CHECK(j["passed"].is_null());
}

TEST_CASE("report: a non-finite scalar is null and scalars read back exactly") {
  ReportData d;
  report::Plot p;
  p.id = "p";
  p.bands = {{0.1, std::numeric_limits<double>::infinity(), "open"}};
  p.limits = {{1.0 / 3.0, "third"}};
  d.plots = {p};
  d.passed = false;
  const nlohmann::json j = nlohmann::json::parse(report::to_json(d));
  CHECK(j["plots"][0]["bands"][0]["from"].get<double>() == 0.1);
  CHECK(j["plots"][0]["bands"][0]["to"].is_null());
  CHECK(j["plots"][0]["limits"][0]["y"].get<double>() == 1.0 / 3.0);
  CHECK(j["passed"] == false);
}

TEST_CASE("report: the page holds the data once and the title escaped") {
  ReportData d;
  d.command = "lift";
  d.title = "lift <b>&</b>";
  const std::string html = report::render_html(d);
  CHECK(html.find("<title>lift &lt;b&gt;&amp;&lt;/b&gt;</title>") != std::string::npos);
  CHECK(html.find("{{camopt:") == std::string::npos);
  const std::string tag = "id=\"camopt-data\"";
  CHECK(html.find(tag) != std::string::npos);
  CHECK(html.find(tag, html.find(tag) + 1) == std::string::npos);
  CHECK(page_data(html)["title"] == d.title);
  // uPlot is inlined: the page fetches nothing
  CHECK(html.find("uPlot") != std::string::npos);
  CHECK(html.find("src=\"http") == std::string::npos);
}

// the bucket check: for every bucket [b n / B, (b + 1) n / B) of B = (max - 2) / 2, its
// smallest and largest values are among the kept points of that bucket
void check_buckets(const std::vector<double>& y, std::size_t max_points) {
  const std::vector<std::size_t> keep = report::decimation_indices(y, max_points);
  const std::size_t n = y.size();
  REQUIRE(keep.size() <= max_points);
  REQUIRE(keep.front() == 0);
  REQUIRE(keep.back() == n - 1);
  for (std::size_t i = 1; i < keep.size(); ++i) REQUIRE(keep[i] > keep[i - 1]);
  const std::size_t buckets = (max_points - 2) / 2;
  std::size_t k = 0;
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t begin = b * n / buckets, end = (b + 1) * n / buckets;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = begin; i < end; ++i) lo = std::min(lo, y[i]), hi = std::max(hi, y[i]);
    bool has_lo = false, has_hi = false;
    while (k < keep.size() && keep[k] < begin) ++k;
    for (std::size_t m = k; m < keep.size() && keep[m] < end; ++m) {
      has_lo = has_lo || y[keep[m]] == lo;
      has_hi = has_hi || y[keep[m]] == hi;
    }
    INFO("bucket " << b << " of " << buckets << " [" << begin << ", " << end << ")");
    CHECK(has_lo);
    CHECK(has_hi);
  }
}

TEST_CASE("report: decimation keeps every bucket's smallest and largest value and the ends") {
  std::mt19937 rng(20240611);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::size_t n : {4001, 10007, 100000}) {
    std::vector<double> y(n);
    for (std::size_t i = 0; i < n; ++i) y[i] = std::sin(i * 0.001) + 0.3 * noise(rng);
    y[n / 3] = 50.0;  // a single spike survives
    y[2 * n / 3] = -50.0;
    INFO("n = " << n);
    check_buckets(y, report::kMaxDisplayPoints);
    check_buckets(y, 100);
    const auto keep = report::decimation_indices(y, report::kMaxDisplayPoints);
    CHECK(std::find(keep.begin(), keep.end(), n / 3) != keep.end());
    CHECK(std::find(keep.begin(), keep.end(), 2 * n / 3) != keep.end());
  }
  // at or under the limit: every point
  const std::vector<double> short_series(report::kMaxDisplayPoints, 1.0);
  CHECK(report::decimation_indices(short_series, report::kMaxDisplayPoints).size() == short_series.size());
}

TEST_CASE("report: decimate() gives a long series on a shared x its own decimated x") {
  ReportData d;
  report::Plot p;
  p.id = "long";
  for (int i = 0; i < 20000; ++i) p.x_values.push_back(0.01 * i);
  report::Series s;
  for (int i = 0; i < 20000; ++i) s.y.push_back(std::cos(0.01 * i) * (i == 12345 ? 3.0 : 1.0));
  p.series.push_back(s);
  d.plots.push_back(p);
  report::decimate(d);
  const report::Series& out = d.plots[0].series[0];
  REQUIRE(out.y.size() <= static_cast<std::size_t>(report::kMaxDisplayPoints));
  REQUIRE(out.x.size() == out.y.size());
  CHECK(d.plots[0].x_values.empty());
  // every kept point is a point of the series, x with its y
  for (std::size_t i = 0; i < out.x.size(); ++i) {
    const auto j = static_cast<std::size_t>(std::lround(out.x[i] / 0.01));
    REQUIRE(out.y[i] == s.y[j]);
  }
  CHECK(*std::max_element(out.y.begin(), out.y.end()) == *std::max_element(s.y.begin(), s.y.end()));
}

}  // namespace
}  // namespace camopt::test
