// The four pipeline variants of docs/design.md ("Variants"), as presets of one config field.
#pragma once

#include <optional>
#include <string_view>

#include "sonarfusion/config.hpp"

namespace sonarfusion {

enum class Variant {
    FlsOnly,    // FLS updates alone (the false-slope baseline)
    CarveOnly,  // PS alone: carving plus PS end-point hits over an unknown map
    Paper,      // the paper's rules to the letter: every pixel-point counts, no PS confirmation
    Fused,      // product default: the paper plus per-frame counting and PS confirmation
};

[[nodiscard]] std::string_view variantName(Variant v);
[[nodiscard]] std::optional<Variant> parseVariant(std::string_view name);

// Sets cfg.update for the variant; everything else in cfg is left as it is.
void applyVariant(Variant v, MapperConfig& cfg);

}  // namespace sonarfusion
