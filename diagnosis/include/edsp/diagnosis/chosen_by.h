#pragma once
// Which candidate set a calibration applies won (calibration_set.h): the
// identified effects, the selected ones, those grown forward, or the whole
// vocabulary pruned backward. The names are the report's and the model's
// `calibration.chosen_by`, which users' scripts read.

namespace edsp::gap {

enum class ChosenBy { kIdentified, kSelected, kForward, kBackward };

const char* ChosenByName(ChosenBy how);  // "identified", "selected", "forward", "backward"

}  // namespace edsp::gap
