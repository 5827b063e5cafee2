#pragma once
// What a diagnosis concludes (diagnose.h's Diagnosis::conclusion): effects
// of the vocabulary, nothing beyond the noise, something no effect of it
// explains, or effects and such a thing. The names are the report's
// `conclusion` (interfaces.md §4), which users' scripts read. `none` and
// `unknown` are also the vocabulary's two pseudo-effects: the report ranks
// them, and lists `unknown` among what an effect is ambiguous with, by
// these names.

namespace edsp::gap {

enum class Conclusion { kEffects, kNone, kUnknown, kEffectsAndUnknown };

const char* ConclusionName(Conclusion conclusion);  // "effects", "none", "unknown", "effects+unknown"

// From what was found: effects selected, and something beyond the vocabulary.
Conclusion Conclude(bool effects, bool unknown);
// Whether it says something outside the vocabulary is at work.
bool NamesUnknown(Conclusion conclusion);
// The same effects (or none), once something outside the vocabulary is found too.
Conclusion WithUnknown(Conclusion conclusion);

}  // namespace edsp::gap
