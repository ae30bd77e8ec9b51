#pragma once
// "a", "a,b,c" or "START:STOP:COUNT" (COUNT points, both ends included) -> values
#include <string>
#include <vector>

namespace camopt::jobs {

std::vector<double> parse_range(const std::string& option, const std::string& text);

}  // namespace camopt::jobs
