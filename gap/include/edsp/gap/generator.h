#pragma once
// Which virtual rig draws a benchmark's data, and with which encoder columns.

namespace edsp::gap {

// kRig: edsp's own virtual rig (edsp-sim rig's model); kBlind: the
// independently written rig (blindrig/), which draws its own tracker (rate
// 10–1000 Hz, σ 2–20 µm, with or without encoders).
enum class Generator { kRig, kBlind };
const char* GeneratorName(Generator generator);  // "rig" | "blind": the command line's and the JSON's words

// The blind generator's encoder columns: as each scenario drew them, in
// every scenario, or in none (so that the checks that need their absence
// run on every draw).
enum class EncoderColumns { kDrawn, kWith, kWithout };
const char* EncoderColumnsName(EncoderColumns columns);  // "drawn" | "with" | "without"

}  // namespace edsp::gap
