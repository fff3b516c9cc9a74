// The convolution method's anchor knots and tiles (core/src/kernel_table.h,
// core/src/anchored_convolution.h): knots mirror-symmetric about the frame's middle, so that mirror
// pairs of anchors can share their PSFs, and tiles that hold whole anchor cells or part of one,
// so that a tile meets only the knots of its own cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "convolution/anchored_convolution.h"
#include "fft/column_fft.h"
#include "convolution/kernel_table.h"

using wavecam::detail::AnchorAxis;
using wavecam::detail::convolution_fft_length;
using wavecam::detail::pass_period;
using wavecam::detail::tile_edges;

TEST(AnchorAxis, EvenKnotsAreMirrorSymmetricAndWithinAPixelOfEven) {
    for (int inset : {0, 7, 53})
        for (int span : {1, 2, 31, 100, 1920})
            for (int cells : {1, 2, 3, 7, 8, 24, 200}) {
                const AnchorAxis a = AnchorAxis::even(inset, span, cells);
                const int n = a.cells();
                // (one more cell where the span is odd and the count even: no knot on a half pixel)
                ASSERT_EQ(n, std::min(cells, span) + (span % 2 == 1 && std::min(cells, span) % 2 == 0))
                    << inset << " " << span << " " << cells;
                EXPECT_EQ(a.knots.front(), inset);
                EXPECT_EQ(a.knots.back(), inset + span);
                for (int k = 0; k <= n; ++k) EXPECT_EQ(a.knots[k] + a.knots[n - k], 2 * inset + span);
                int narrowest = span, widest = 0;
                for (int k = 0; k < n; ++k) {
                    narrowest = std::min(narrowest, a.knots[k + 1] - a.knots[k]);
                    widest = std::max(widest, a.knots[k + 1] - a.knots[k]);
                }
                EXPECT_GE(narrowest, 1);
                EXPECT_LE(widest - narrowest, 2) << inset << " " << span << " " << cells;
            }
}

TEST(TileEdges, TilesOfCellsHoldWholeCellsOrFallBackToEvenTiles) {
    for (int radius : {1, 13, 53})
        for (int span : {64, 500, 1920})
            for (int cells : {1, 3, 7, 16})
                for (int tile : {2 * radius, 128, 327, 1000}) {
                    const int length = span + 2 * radius;
                    const AnchorAxis a = AnchorAxis::even(radius, span, cells);
                    const std::vector<int> even = tile_edges(a, length, tile, radius, false);
                    const std::vector<int> e = tile_edges(a, length, tile, radius, true);
                    ASSERT_EQ(e.front(), 0);
                    ASSERT_EQ(e.back(), length);
                    for (size_t k = 0; k + 1 < e.size(); ++k) ASSERT_LT(e[k], e[k + 1]);
                    if (tile >= length) {
                        EXPECT_EQ(e, (std::vector<int>{0, length}));  // one tile
                        continue;
                    }
                    for (size_t k = 0; k + 1 < even.size(); ++k) EXPECT_LE(even[k + 1] - even[k], tile);
                    if (e == even) continue;  // cells too narrow for tiles of R, or even tiles asked for
                    for (size_t k = 0; k + 1 < e.size(); ++k) {
                        EXPECT_LE(e[k + 1] - e[k], tile);
                        EXPECT_GE(e[k + 1] - e[k], radius);  // the overlap-add's passes need it
                    }
                    // a tile is part of one cell or whole cells: a tile spanning cells starts and
                    // ends on cells' edges, so it meets no knot of a cell it holds only in part
                    const std::vector<int> cell = wavecam::detail::cell_edges(a, length);
                    for (size_t k = 0; k + 1 < e.size(); ++k)
                        if (a.cell_of(e[k]) != a.cell_of(e[k + 1] - 1)) {
                            EXPECT_TRUE(std::binary_search(cell.begin(), cell.end(), e[k])) << e[k] << ", tile " << tile;
                            EXPECT_TRUE(std::binary_search(cell.begin(), cell.end(), e[k + 1]))
                                << e[k + 1] << ", tile " << tile;
                        }
                }
}

// The overlap-add passes: a tile writes R beyond itself, so two tiles of one pass (pass_period
// apart) must never write the same pixel; tiles of 2 R or more take every other tile, tiles of
// R or more every third, on cells or even, whatever the last tile's width.
TEST(TileEdges, TilesOfOnePassNeverWriteTheSamePixel) {
    for (int radius : {1, 13, 53, 61})
        for (int span : {64, 500, 1920})
            for (int cells : {1, 3, 7, 16, 40})
                for (int tile : {radius, radius + 7, 2 * radius - 1, 2 * radius, 128, 327})
                    for (bool on_cells : {false, true}) {
                        const int length = span + 2 * radius;
                        const std::vector<int> e =
                            tile_edges(AnchorAxis::even(radius, span, cells), length, tile, radius, on_cells);
                        const int period = pass_period(e, radius), tiles = int(e.size()) - 1;
                        int narrowest = length;
                        for (int k = 0; k + 1 < tiles; ++k) narrowest = std::min(narrowest, e[k + 1] - e[k]);
                        if (narrowest >= 2 * radius) {
                            EXPECT_EQ(period, 2) << radius << " " << span << " " << tile;
                        }
                        if (narrowest >= radius) {
                            EXPECT_LE(period, 3) << radius << " " << span << " " << tile;
                        }
                        for (int k = 0; k < tiles; ++k)
                            for (int j = k + period; j < tiles; j += period)
                                EXPECT_LE(e[k + 1] + radius, e[j] - radius)
                                    << "tiles " << k << " and " << j << ", R " << radius << ", tile " << tile;
                    }
}

// Each axis's transform as long as that axis needs: tile + 2 R where tiles cut it, the domain's
// own length where one tile covers it (a strip's short side), never the other axis's length.
TEST(TileEdges, EachAxisTransformsItsOwnLength) {
    const int radius = 122, tile = 314;
    EXPECT_EQ(convolution_fft_length(tile, radius, 4340), wavecam::detail::fft_friendly_size(tile + 2 * radius));
    EXPECT_EQ(convolution_fft_length(tile, radius, 308), wavecam::detail::fft_friendly_size(308));
    EXPECT_LT(convolution_fft_length(tile, radius, 308), tile + 2 * radius);
    for (int length : {2 * radius + 2, 300, 1000, 4340}) {
        const int n = convolution_fft_length(tile, radius, length);
        EXPECT_GE(n, std::min(length, tile + 2 * radius)) << length;  // the tile and its kernels' reach, or the axis
    }
}
