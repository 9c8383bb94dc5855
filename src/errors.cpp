#include "ricci/errors.hpp"

namespace ricci {

std::vector<OptionFix> fixes_of(std::initializer_list<std::pair<const char*, const char*>> pairs) {
  std::vector<OptionFix> fixes;
  for (const auto& [option, value] : pairs) fixes.push_back(OptionFix{option, value});
  return fixes;
}

}  // namespace ricci
