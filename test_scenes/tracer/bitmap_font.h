// A 5x7 bitmap font (the HD44780 LCD controller's character ROM glyphs): A-Z, 0-9, space
// and . - : / = ; lower case letters draw as upper case.
#pragma once

namespace wavecam::trace {

constexpr int kGlyphColumns = 5;
constexpr int kGlyphRows = 7;

bool has_glyph(char c);
// Whether the glyph of c has ink at column (0 = left) and row (0 = top); false for a
// character without a glyph.
bool glyph_pixel(char c, int column, int row);

}  // namespace wavecam::trace
