// variant.hpp: the one list of variants, their names and presets.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>

#include "sonarfusion/variant.hpp"

using namespace sonarfusion;

TEST(Variant, EveryVariantIsListedOnceAndItsNameParsesBack) {
    std::set<std::string> names;
    for (Variant v : kVariants) {
        const std::string name(variantName(v));
        EXPECT_NE(name, "unknown");
        EXPECT_TRUE(names.insert(name).second) << name << " listed twice";
        ASSERT_TRUE(parseVariant(name).has_value()) << name;
        EXPECT_EQ(*parseVariant(name), v);
    }
    EXPECT_EQ(names.size(), 4u);
    EXPECT_FALSE(parseVariant("fusion").has_value());
    EXPECT_FALSE(parseVariant("").has_value());
}

TEST(Variant, ChoicesNameThemInThePapersOrder) {
    EXPECT_EQ(variantChoices(), "fls_only, carve_only, paper or fused");
    EXPECT_EQ(kVariants.front(), Variant::FlsOnly);
    EXPECT_EQ(kVariants.back(), Variant::Fused);
}

TEST(Variant, PresetsDifferWhereTheTableSaysSo) {
    MapperConfig fls_only, carve_only, paper, fused;
    applyVariant(Variant::FlsOnly, fls_only);
    applyVariant(Variant::CarveOnly, carve_only);
    applyVariant(Variant::Paper, paper);
    applyVariant(Variant::Fused, fused);
    EXPECT_FALSE(fls_only.update.ps_carving_enabled);
    EXPECT_FALSE(fls_only.update.require_ps_observation);
    EXPECT_FALSE(carve_only.update.fls_enabled);
    EXPECT_FALSE(paper.update.fls_once_per_frame);
    EXPECT_DOUBLE_EQ(paper.update.p_free, 0.4);
    EXPECT_TRUE(fused.update.fls_once_per_frame);
    EXPECT_TRUE(fused.update.require_ps_observation);
    EXPECT_TRUE(fused.update.ps_endpoint_hits);
}

TEST(Variant, RequireVariantNamesTheChoicesAndTheBadName) {
    EXPECT_EQ(requireVariant("paper", "--variant"), Variant::Paper);
    try {
        (void)requireVariant("fusion", "--variant");
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "--variant must be fls_only, carve_only, paper or fused (not 'fusion')");
    }
}
