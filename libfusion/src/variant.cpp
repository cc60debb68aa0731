#include "sonarfusion/variant.hpp"

#include <stdexcept>

namespace sonarfusion {

std::string_view variantName(Variant v) {
    switch (v) {
        case Variant::FlsOnly: return "fls_only";
        case Variant::CarveOnly: return "carve_only";
        case Variant::Paper: return "paper";
        case Variant::Fused: return "fused";
    }
    return "unknown";
}

std::optional<Variant> parseVariant(std::string_view name) {
    for (Variant v : kVariants) {
        if (variantName(v) == name) return v;
    }
    return std::nullopt;
}

Variant requireVariant(std::string_view name, std::string_view what) {
    if (const auto v = parseVariant(name)) return *v;
    throw std::invalid_argument(std::string(what) + " must be " + variantChoices() + " (not '" + std::string(name) +
                                "')");
}

std::string variantChoices() {
    std::string s;
    for (std::size_t i = 0; i < kVariants.size(); ++i) {
        if (i > 0) s += i + 1 == kVariants.size() ? " or " : ", ";
        s += variantName(kVariants[i]);
    }
    return s;
}

void applyVariant(Variant v, MapperConfig& cfg) {
    UpdateConfig& u = cfg.update;
    u = UpdateConfig{};  // fused defaults
    switch (v) {
        case Variant::Fused:
            break;
        case Variant::Paper:
            // docs/design.md ("FLS log-odds update"): the paper-literal prototype used P_o 0.7, P_f 0.4,
            // alpha_F 1, alpha_P 1, one update per pixel-point, no confirmation.
            u.p_occupied = 0.7;
            u.p_free = 0.4;
            u.alpha_fls = 1.0;
            u.alpha_ps = 1.0;
            u.fls_once_per_frame = false;
            u.fls_arc_spacing_voxels = 0.0;  // N_v = 5 at every range
            u.fls_free_space = false;
            u.ps_endpoint_hits = false;  // Eq. 13 leaves the end voxel alone
            u.ps_carve_noise_sigmas = 0.0;        // Eq. 13 carves up to the selected range
            u.ps_carve_echo_window_voxels = 0.0;
            u.ps_carve_spare_echo_share = 0.0;    // and every voxel on the way
            u.fls_free_space_noise_sigmas = 0.0;
            u.fls_highlight_above_seabed = false;  // range alone says what the seabed cannot explain
            u.fls_seabed_at_footprint = false;     // the detector's plane, as the first rules were measured with
            u.fls_seabed_judged_later = false;
            cfg.ps_selection.weak_echoes_group = false;  // tau alone (paper 2.3)
            u.require_ps_observation = false;
            break;
        case Variant::FlsOnly:
            u.ps_carving_enabled = false;
            u.ps_endpoint_hits = false;
            u.require_ps_observation = false;
            break;
        case Variant::CarveOnly:
            u.fls_enabled = false;
            u.ps_endpoint_hits = true;
            break;
    }
}

}  // namespace sonarfusion
