// The four pipeline variants of docs/design.md ("Variants"), as presets of one config field.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "sonarfusion/config.hpp"

namespace sonarfusion {

enum class Variant {
    FlsOnly,    // FLS updates alone (the false-slope baseline)
    CarveOnly,  // PS alone: carving plus PS end-point hits over an unknown map
    Paper,      // the paper's rules to the letter: every pixel-point counts, no PS confirmation
    Fused,      // product default: the paper plus per-frame counting and PS confirmation
};

// Every variant once, in the paper's order: the one list that parsers, help
// texts and tools iterate (report.json and the tables use this order too).
inline constexpr std::array<Variant, 4> kVariants = {Variant::FlsOnly, Variant::CarveOnly, Variant::Paper,
                                                     Variant::Fused};
static_assert(kVariants.size() == static_cast<std::size_t>(Variant::Fused) + 1, "kVariants lists every Variant");

[[nodiscard]] std::string_view variantName(Variant v);
// "fls_only, carve_only, paper or fused": the names, for help texts and errors.
[[nodiscard]] std::string variantChoices();
[[nodiscard]] std::optional<Variant> parseVariant(std::string_view name);
// parseVariant, or std::invalid_argument "<what> must be fls_only, carve_only,
// paper or fused (not 'NAME')" for command lines and config readers.
[[nodiscard]] Variant requireVariant(std::string_view name, std::string_view what);

// Sets cfg.update for the variant; everything else in cfg is left as it is.
void applyVariant(Variant v, MapperConfig& cfg);

}  // namespace sonarfusion
