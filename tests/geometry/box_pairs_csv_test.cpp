// The pairs CSV (geometry/box_pairs_csv.h) read whole and a chunk at a time: the same pairs, in
// order, with the doubles that were printed (17 significant digits) and the ids as written.
#include "nestwalk/geometry/box_pairs_csv.h"

#include "tests/geometry/box_pair_generators.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

namespace nestwalk {
namespace {

std::string csvOf(const std::vector<boxgen::Pair>& pairs) {
  std::string text = "id";
  for (char p : {'a', 'b'})
    for (const char* f : {"cx", "cy", "cz", "ux", "uy", "uz", "vx", "vy", "vz", "wx", "wy", "wz", "ex", "ey", "ez"})
      text += std::string(",") + p + f;
  text += "\n";
  char buf[40];
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    text += "pair " + std::to_string(k);
    for (const Obb<double>* b : {&pairs[k].first, &pairs[k].second}) {
      const double* fields = b->center.data();  // centre, axes column by column, half extents
      for (int f = 0; f < 15; ++f) std::snprintf(buf, sizeof buf, ",%.17g", fields[f]), text += buf;
    }
    text += "\n";
  }
  return text;
}

void expectSameBox(const Obb<double>& read, const Obb<double>& written) {
  EXPECT_EQ(read.center, written.center);
  EXPECT_EQ(read.axes, written.axes);
  EXPECT_EQ(read.halfExtents, written.halfExtents);
}

TEST(BoxPairsCsv, ChunksReadTheSamePairsAsTheWholeFile) {
  boxgen::Gen g(5);
  std::vector<boxgen::Pair> written;
  for (int k = 0; k < 50; ++k) written.push_back(boxgen::randomPair(g, {500000.25, 7000000.5, 120.0}));
  const std::string text = csvOf(written);

  std::istringstream whole(text);
  const std::vector<BoxPair> all = readBoxPairs(whole, "pairs.csv");
  ASSERT_EQ(all.size(), written.size());
  for (std::size_t k = 0; k < all.size(); ++k) {
    EXPECT_EQ(all[k].id, "pair " + std::to_string(k));
    expectSameBox(all[k].a, written[k].first);
    expectSameBox(all[k].b, written[k].second);
  }

  for (const std::size_t chunk : {std::size_t(1), std::size_t(7), std::size_t(50), std::size_t(64)}) {
    std::istringstream in(text);
    BoxPairsReader reader(in, "pairs.csv");
    std::vector<BoxPair> got, part;
    while (reader.read(part, chunk)) {
      EXPECT_LE(part.size(), chunk);
      got.insert(got.end(), part.begin(), part.end());
    }
    EXPECT_TRUE(part.empty());
    ASSERT_EQ(got.size(), all.size()) << "chunks of " << chunk;
    for (std::size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].id, all[k].id);
      expectSameBox(got[k].a, all[k].a);
      expectSameBox(got[k].b, all[k].b);
    }
  }
}

}  // namespace
}  // namespace nestwalk
