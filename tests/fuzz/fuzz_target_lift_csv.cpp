// libFuzzer harness: camopt::fuzz::target_lift_csv (see fuzz_entry.hpp); built with -DCAMOPT_BUILD_FUZZ=ON
// by clang, run by scripts/fuzz.sh
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_entry.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  (void)camopt::fuzz::target_lift_csv(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
