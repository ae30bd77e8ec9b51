#include "camopt/jobs/range_option.hpp"

#include <charconv>
#include <cmath>
#include <sstream>

#include "camopt/core/error.hpp"

namespace camopt::jobs {

namespace {
double number(const std::string& option, const std::string& text, const std::string& item) {
  double v = 0.0;
  const auto* end = item.data() + item.size();
  const auto r = std::from_chars(item.data(), end, v);
  if (item.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(v))
    throw InputError(option + ": '" + item + "' in '" + text + "' is not a finite number");
  return v;
}
}  // namespace

std::vector<double> parse_range(const std::string& option, const std::string& text) {
  std::vector<std::string> parts;
  const char sep = text.find(':') != std::string::npos ? ':' : ',';
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, sep)) parts.push_back(item);
  if (sep == ',' || parts.size() == 1) {
    std::vector<double> v;
    for (const auto& p : parts) v.push_back(number(option, text, p));
    if (v.empty()) throw InputError(option + ": empty value");
    return v;
  }
  if (parts.size() != 3)
    throw InputError(option + ": '" + text + "' must be a value, a list a,b,c or START:STOP:COUNT");
  const double a = number(option, text, parts[0]), b = number(option, text, parts[1]);
  const double count = number(option, text, parts[2]);
  if (count < 1 || count != std::floor(count) || count > 100000)
    throw InputError(option + ": COUNT '" + parts[2] + "' must be a whole number in [1, 100000]");
  const int n = static_cast<int>(count);
  if (n == 1 && a != b) throw InputError(option + ": COUNT 1 needs START == STOP");
  std::vector<double> v(n);
  for (int i = 0; i < n; ++i) v[i] = n == 1 ? a : a + (b - a) * i / (n - 1);
  return v;
}

}  // namespace camopt::jobs
