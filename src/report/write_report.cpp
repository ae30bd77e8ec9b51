// write_report(): collect, render and write the page atomically beside the results.
#include "camopt/io/atomic_file.hpp"
#include "camopt/report/report.hpp"

namespace camopt::report {

std::filesystem::path report_path(const std::filesystem::path& source) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(source, ec))
    return source.parent_path() / (source.stem().string() + ".report.html");
  return source / "report.html";
}

std::filesystem::path write_report(const std::filesystem::path& source) {
  // the page, made whole before anything is written
  const std::string html = render_html(collect(source));
  const std::filesystem::path path = report_path(source);
  // the page is rebuilt from the results at any time (camopt report): renamed into place
  // without waiting for the disk, which would cost the shortest runs a fifth of their time
  io::write_text_atomic(path.string(), html, io::Durability::renamed);
  return path;
}

}  // namespace camopt::report
