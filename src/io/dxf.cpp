#include "camopt/io/dxf.hpp"

#include <charconv>

#include "camopt/core/error.hpp"

namespace camopt::io {

std::string dxf_closed_polyline(const std::vector<double>& x, const std::vector<double>& y, const std::string& layer) {
  CAMOPT_ASSERT(x.size() == y.size() && x.size() >= 3);
  std::string out;
  auto pair = [&](int code, const std::string& value) {
    out += std::to_string(code) + "\n" + value + "\n";
  };
  // the shortest fixed-point text that reads back to the same double (no exponent, no locale)
  auto number = [](double v) {
    char b[400];
    const auto r = std::to_chars(b, b + sizeof b, v + 0.0, std::chars_format::fixed);
    return std::string(b, r.ptr);
  };
  pair(999, "camopt cam profile [mm]");
  pair(0, "SECTION");
  pair(2, "HEADER");
  pair(9, "$INSUNITS");
  pair(70, "4");  // millimetres
  pair(0, "ENDSEC");
  pair(0, "SECTION");
  pair(2, "ENTITIES");
  pair(0, "POLYLINE");
  pair(8, layer);
  pair(66, "1");  // vertices follow
  pair(70, "1");  // closed
  for (std::size_t i = 0; i < x.size(); ++i) {
    pair(0, "VERTEX");
    pair(8, layer);
    pair(10, number(x[i]));
    pair(20, number(y[i]));
    pair(30, number(0.0));
  }
  pair(0, "SEQEND");
  pair(8, layer);
  pair(0, "ENDSEC");
  pair(0, "EOF");
  return out;
}

}  // namespace camopt::io
