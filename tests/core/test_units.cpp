#include <gtest/gtest.h>

#include <cmath>

#include "wavecam/units.h"

using namespace wavecam;

TEST(Units, LengthsConvertToMetres) {
    EXPECT_DOUBLE_EQ(parse_length("0.3mm", "pinhole").value, 0.3e-3);
    EXPECT_DOUBLE_EQ(parse_length("550nm", "wavelength").value, 550e-9);
    EXPECT_DOUBLE_EQ(parse_length("12um", "x").value, 12e-6);
    EXPECT_DOUBLE_EQ(parse_length("2.5cm", "x").value, 0.025);
    EXPECT_DOUBLE_EQ(parse_length("3m", "x").value, 3.0);
    EXPECT_DOUBLE_EQ(parse_length("1e-1mm", "x").value, 1e-4);
}

TEST(Units, AnglesConvertToRadians) {
    EXPECT_NEAR(parse_angle("50deg", "fov").value, 50 * M_PI / 180, 1e-15);
    EXPECT_DOUBLE_EQ(parse_angle("0.5rad", "fov").value, 0.5);
}

TEST(Units, InfinityOnlyWhereAllowed) {
    EXPECT_TRUE(std::isinf(parse_length_or_inf("inf", "source-distance").value));
    EXPECT_FALSE(parse_length("inf", "pinhole").ok());
}

TEST(Units, ErrorsNameTheFieldAndTheExpectation) {
    const auto missing_unit = parse_length("0.3", "pinhole");
    ASSERT_FALSE(missing_unit.ok());
    EXPECT_NE(missing_unit.error.find("pinhole"), std::string::npos);
    EXPECT_NE(missing_unit.error.find("mm"), std::string::npos);
    EXPECT_NE(missing_unit.error.find("'0.3'"), std::string::npos);
    EXPECT_FALSE(parse_length("0.3 mm", "pinhole").ok());
    EXPECT_FALSE(parse_length("mm", "pinhole").ok());
    EXPECT_FALSE(parse_length("", "pinhole").ok());
    EXPECT_FALSE(parse_length("0.3deg", "pinhole").ok());
    EXPECT_FALSE(parse_angle("50", "fov").ok());
    EXPECT_FALSE(parse_angle("nandeg", "fov").ok());
    EXPECT_FALSE(parse_whole_number("-3", "resolution", 1, 16384).ok());
    EXPECT_FALSE(parse_whole_number("12px", "resolution", 1, 16384).ok());
    EXPECT_FALSE(parse_whole_number("16385", "resolution", 1, 16384).ok());
    EXPECT_EQ(parse_whole_number("255", "resolution", 1, 16384).value, 255);
    EXPECT_EQ(parse_whole_number("12px", "resolution", 1, 16384).error,
              "resolution: expected a whole number from 1 to 16384, got '12px'");
}

TEST(Units, SizesConvertToBytes) {
    EXPECT_DOUBLE_EQ(parse_bytes("16GiB", "max-memory").value, 16.0 * 1024 * 1024 * 1024);
    EXPECT_DOUBLE_EQ(parse_bytes("512MiB", "max-memory").value, 512.0 * 1024 * 1024);
    EXPECT_DOUBLE_EQ(parse_bytes("2GB", "max-memory").value, 2e9);
    EXPECT_DOUBLE_EQ(parse_bytes("1.5KB", "max-memory").value, 1500);
    for (const char* bad : {"12", "0GiB", "-1MiB", "1 GiB", "1gib", ""})
        EXPECT_EQ(parse_bytes(bad, "max-memory").error.rfind("max-memory: expected a size > 0 with a unit", 0), 0u)
            << bad;
}
