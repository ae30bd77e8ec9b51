#pragma once
// the page's assets, inlined at build time (cmake/embed_report_assets.cmake writes them from
// node_modules/uplot/dist and src/report/web into the build tree)
#include <string_view>

namespace camopt::report::assets {

extern const std::string_view template_html;  // src/report/web/template.html
extern const std::string_view report_js;      // src/report/web/report.js
extern const std::string_view report_css;     // src/report/web/report.css
extern const std::string_view uplot_js;       // node_modules/uplot/dist/uPlot.iife.min.js
extern const std::string_view uplot_css;      // node_modules/uplot/dist/uPlot.min.css

}  // namespace camopt::report::assets
