#include "edsp/gap/generator.h"

namespace edsp::gap {

const char* GeneratorName(Generator generator) { return generator == Generator::kBlind ? "blind" : "rig"; }

const char* EncoderColumnsName(EncoderColumns columns) {
  switch (columns) {
    case EncoderColumns::kDrawn: return "drawn";
    case EncoderColumns::kWith: return "with";
    case EncoderColumns::kWithout: return "without";
  }
  return "drawn";
}

}  // namespace edsp::gap
