#include "edsp/diagnosis/chosen_by.h"

#include <cstddef>
#include <iterator>

namespace edsp::gap {

namespace {

// In the enum's order.
constexpr const char* kChosenByNames[] = {"identified", "selected", "forward", "backward"};
static_assert(std::size(kChosenByNames) == static_cast<std::size_t>(ChosenBy::kBackward) + 1, "a name per candidate");

}  // namespace

const char* ChosenByName(ChosenBy how) { return kChosenByNames[static_cast<std::size_t>(how)]; }

}  // namespace edsp::gap
