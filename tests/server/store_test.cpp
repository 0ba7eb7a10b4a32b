// The embedded store: datasets survive a restart bit for bit, and an interrupted write leaves nothing.
#include <fstream>

#include <gtest/gtest.h>

#include "store/embedded_store.hpp"
#include "test_support.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {
namespace fs = std::filesystem;

std::shared_ptr<Dataset> dataset(const std::string& id, int n) {
  TrailSetBuilder b;
  for (int i = 0; i < n; ++i) {
    Sample s;
    s.t = 1000 + i, s.lat = 10 + i * 1e-3f, s.lon = 179.9f + i * 0.05f;  // crosses 180° on the way
    if (s.lon >= 180) s.lon -= 360;
    s.alt = i % 7 ? static_cast<float>(i) : Sample::kUnknown, s.speed = 3, s.on_ground = i < 3;
    b.add("abcdef", "TEST", s);
  }
  auto ds = std::make_shared<Dataset>();
  ds->id = id, ds->name = id, ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->ingest = {{"rows", n}};
  ds->trails = std::make_shared<const TrailSet>(b.build());
  return ds;
}

TEST(EmbeddedStore, RoundTripAfterRestart) {
  test::TempDir tmp;
  const auto ds = dataset("a", 100);
  {
    EmbeddedStore s(tmp.path());
    s.put(ds);
  }
  EmbeddedStore s(tmp.path());
  ASSERT_TRUE(s.contains("a"));
  const auto back = s.get("a");
  const auto &p = back->trails->points(), &q = ds->trails->points();
  ASSERT_EQ(p.size(), q.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p.t[i], q.t[i]);
    EXPECT_EQ(p.lon[i], q.lon[i]);
    EXPECT_EQ(std::isnan(p.alt[i]), std::isnan(q.alt[i]));
    EXPECT_EQ(p.on_ground[i], q.on_ground[i]);
  }
  ASSERT_EQ(back->trails->num_flights(), 1u);
  EXPECT_TRUE(back->trails->flights()[0].crosses_antimeridian);
  EXPECT_EQ(back->ingest["rows"], 100);
}

TEST(EmbeddedStore, InterruptedWriteLeavesNoDataset) {
  test::TempDir tmp;
  {
    EmbeddedStore s(tmp.path());
    s.put(dataset("kept", 10));
  }
  // What a kill during put() leaves behind: a half-written folder in tmp/, and no manifest.
  fs::create_directories(tmp.path() / "tmp" / "half.1234");
  std::ofstream(tmp.path() / "tmp" / "half.1234" / "t.bin") << "partial";
  // A dataset folder without its manifest (written last) is not a dataset either.
  fs::create_directories(tmp.path() / "datasets" / "broken");
  std::ofstream(tmp.path() / "datasets" / "broken" / "t.bin") << "partial";
  {
    // A CLI verb opening the folder of a live server must not touch its writes in flight.
    EmbeddedStore cli(tmp.path());
    EXPECT_TRUE(cli.contains("kept"));
    EXPECT_FALSE(cli.contains("half"));
    EXPECT_TRUE(fs::exists(tmp.path() / "tmp" / "half.1234" / "t.bin"));
  }
  EmbeddedStore s(tmp.path(), EmbeddedStore::Leftovers::remove);  // as `serve` opens it
  EXPECT_TRUE(s.contains("kept"));
  EXPECT_FALSE(s.contains("half"));
  EXPECT_FALSE(s.contains("broken"));
  EXPECT_TRUE(fs::is_empty(tmp.path() / "tmp"));
  EXPECT_EQ(s.list().size(), 1u);
}

TEST(EmbeddedStore, UnreadableDatasetIsSkippedNeverDeleted) {
  test::TempDir tmp;
  {
    EmbeddedStore s(tmp.path());
    s.put(dataset("good", 10));
    s.put(dataset("bad", 10));
  }
  std::ofstream(tmp.path() / "datasets" / "bad" / "t.bin", std::ios::trunc) << "short";
  EmbeddedStore s(tmp.path());
  EXPECT_EQ(s.get("good")->trails->num_points(), 10u);  // loaded alone, on first use
  EXPECT_THROW(s.get("bad"), Error);
  EXPECT_EQ(s.list().size(), 1u);
  EXPECT_TRUE(fs::exists(tmp.path() / "datasets" / "bad" / "manifest.json"));
}

TEST(EmbeddedStore, ConflictsAndBadIds) {
  test::TempDir tmp;
  EmbeddedStore s(tmp.path());
  s.put(dataset("x", 5));
  try {
    s.put(dataset("x", 5));
    FAIL() << "expected a conflict";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::conflict);
    EXPECT_EQ(e.param(), "name");
  }
  EXPECT_THROW(s.put(dataset("../evil", 5)), Error);
  EXPECT_THROW(s.put(dataset("", 5)), Error);
  EXPECT_EQ(dataset_id_from_name("Europe SO6 (2018)!"), "europe-so6-2018");
}

}  // namespace
}  // namespace trailscope::server
