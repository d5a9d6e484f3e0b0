// Tabular AIS readers, geography, dataset preparation and folds by vessel.
#include <cmath>
#include <random>

#include "specht/ais/dataset.h"
#include "specht/classify/crossval.h"
#include "specht/classify/dataset_io.h"
#include "specht/core/error.h"
#include "test_support.h"

namespace specht::ais {
namespace {

using specht::testing::DataDir;
using specht::testing::TempDir;
using specht::testing::WriteFile;

std::vector<Vessel> ReadAll(const std::string& path, PositionStats* stats = nullptr, std::string* layout = nullptr) {
  VesselReader r(path);
  std::vector<Vessel> out;
  Vessel v;
  while (r.Next(v)) out.push_back(v);
  if (stats != nullptr) *stats = r.stats();
  if (layout != nullptr) *layout = r.layout();
  return out;
}

TEST(AisPositionsTest, ShipTypeCodesMapToThePapersClasses) {
  EXPECT_EQ(ClassOfShipType(70), "Cargo-Tanker");
  EXPECT_EQ(ClassOfShipType(89), "Cargo-Tanker");
  EXPECT_EQ(ClassOfShipType(30), "Fishing");
  EXPECT_EQ(ClassOfShipType(69), "Passenger");
  EXPECT_EQ(ClassOfShipType(36), "Pleasure Craft");
  EXPECT_EQ(ClassOfShipType(52), "Tug");
  EXPECT_EQ(ClassOfShipType(32), "Tug");
  EXPECT_EQ(ClassOfShipType(33), "");
  EXPECT_EQ(ClassOfShipType(-1), "");
  EXPECT_EQ(ShipTypeOfDmaText("Towing long/wide"), 32);
  EXPECT_EQ(ShipTypeOfDmaText("Undefined"), -1);
}

// ITU-R M.585: the MID sits at the front of a ship station's MMSI, after the 8 of a
// handheld and the 98 of a craft associated with a parent ship; the other number
// kinds name no vessel's flag.
TEST(AisPositionsTest, FlagMidFollowsTheMmsiFormats) {
  EXPECT_EQ(FlagMid(227306100), 227);  // France
  EXPECT_EQ(FlagMid(316001017), 316);  // Canada
  EXPECT_EQ(FlagMid(775999999), 775);  // the last MID (Venezuela)
  EXPECT_EQ(FlagMid(822712345), 227);  // handheld
  EXPECT_EQ(FlagMid(982271234), 227);  // craft associated with a parent ship
  EXPECT_EQ(FlagMid(3160001), 0);      // coast station 003160001
  EXPECT_EQ(FlagMid(31600001), 0);     // group 031600001
  EXPECT_EQ(FlagMid(992271234), 0);    // aid to navigation
  EXPECT_EQ(FlagMid(111227100), 0);    // SAR aircraft
  EXPECT_EQ(FlagMid(970012345), 0);    // AIS-SART
  EXPECT_EQ(FlagMid(199999999), 0);    // MID 199 is not allocated
  EXPECT_EQ(FlagMid(800012345), 0);    // handheld with MID 000
  EXPECT_EQ(FlagMid(0), 0);
  EXPECT_EQ(FlagMid(1234567890), 0);  // ten digits
}

TEST(AisPositionsTest, SpechtLayoutGroupsVesselsSortsAndDerivesSpeed) {
  const std::string path = TempDir() + "/t.csv";
  // Vessel 1: three reports 60 s apart moving north by 0.01° (1111.95 m in 60 s =
  // 36.0 kn), the second given out of order and once more as an exact duplicate.
  WriteFile(path,
            "mmsi,time,lon,lat,ship_type\n"
            "1,0,-4.5,48.00,70\n1,120,-4.5,48.02,70\n1,60,-4.5,48.01,70\n1,60,-4.5,48.01,70\n"
            "2,0,-4.5,48.00,\nbad,1,2,3,4\n2,10,-4.5,48.00,\n");
  PositionStats s;
  std::string layout;
  const auto v = ReadAll(path, &s, &layout);
  EXPECT_EQ(layout, "specht");
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].mmsi, 1);
  EXPECT_EQ(v[0].ship_type, 70);
  ASSERT_EQ(v[0].reports.size(), 3u);  // the exact duplicate is dropped
  EXPECT_EQ(s.duplicates, 1);
  EXPECT_DOUBLE_EQ(v[0].reports[1].t_s, 60);
  EXPECT_NEAR(v[0].reports[1].sog_kn, 1111.95 / 60 / (1852.0 / 3600), 0.05);
  EXPECT_NEAR(v[0].reports[1].cog_deg, 0.0, 1e-6);
  EXPECT_EQ(v[1].ship_type, -1);
  EXPECT_EQ(s.skipped.at("bad mmsi"), 1);
  EXPECT_THAT(s.first_problem, ::testing::HasSubstr("t.csv:7: bad mmsi"));
}

TEST(AisPositionsTest, NoaaAndDmaLayoutsAreDetectedFromTheHeader) {
  const std::string noaa = TempDir() + "/noaa.csv", dma = TempDir() + "/dma.csv";
  WriteFile(noaa,
            "MMSI,BaseDateTime,LAT,LON,SOG,COG,Heading,VesselName,IMO,CallSign,VesselType,Status,Length,Width,Draft,"
            "Cargo,TransceiverClass\n"
            "367000001,2020-01-01T00:00:00,30.0,-90.0,10.5,90.0,511,X,,,30,0,20,5,2,,A\n"
            "367000001,2020-01-01T00:01:00,30.0,-89.99,10.4,90.0,511,X,,,30,0,20,5,2,,A\n");
  WriteFile(dma,
            "# Timestamp,Type of mobile,MMSI,Latitude,Longitude,Navigational status,ROT,SOG,COG,Heading,IMO,"
            "Callsign,Name,Ship type,Cargo type\n"
            "01/01/2023 00:00:00,Class A,219000001,55.0,12.0,Under way,0,5.0,180.0,180,Unknown,,,Tug,\n"
            "01/01/2023 00:00:10,Class A,219000001,54.9999,12.0,Under way,0,5.0,180.0,180,Unknown,,,Tug,\n");
  std::string layout;
  auto v = ReadAll(noaa, nullptr, &layout);
  EXPECT_EQ(layout, "noaa");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].ship_type, 30);
  EXPECT_DOUBLE_EQ(v[0].reports[0].t_s, 1577836800.0);
  EXPECT_DOUBLE_EQ(v[0].reports[0].sog_kn, 10.5);  // reported, not derived
  v = ReadAll(dma, nullptr, &layout);
  EXPECT_EQ(layout, "dma");
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].ship_type, 52);
  EXPECT_DOUBLE_EQ(v[0].reports[1].t_s, 1672531210.0);
}

TEST(AisPositionsTest, UngroupedInputAndUnknownHeaderAreClearErrors) {
  const std::string path = TempDir() + "/u.csv";
  WriteFile(path, "mmsi,time,lon,lat\n1,0,0,0\n2,0,0,0\n1,5,0,0\n");
  try {
    ReadAll(path);
    FAIL() << "ungrouped input accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("u.csv:4: MMSI 1 appears again"));
  }
  WriteFile(path, "a,b,c\n1,2,3\n");
  EXPECT_THROW(ReadAll(path), InputError);
}

TEST(AisPositionsTest, TruncatedGzipIsAnErrorNamingTheFile) {
  if (DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string whole = specht::testing::ReadFile(DataDir() + "/ais/tracks/brest-dev.csv.gz");
  const std::string path = TempDir() + "/cut.csv.gz";
  WriteFile(path, whole.substr(0, 200000));
  try {
    ReadAll(path);
    FAIL() << "truncated gzip accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("cut.csv.gz"));
  }
}

TEST(AisGeoTest, GreatCircleDistancesAndNearestPointMatchBruteForce) {
  EXPECT_NEAR(GreatCircleMetres(0, 0, 0, 1), 111195.08, 0.01);
  EXPECT_NEAR(GreatCircleMetres(-180, 0, 180, 0), 0.0, 1e-6);
  EXPECT_NEAR(InitialBearingDeg(0, 0, 1, 0), 90.0, 1e-9);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> lon(-180, 180), lat(-80, 80);
  std::vector<GeoPoint> pts(2000);
  for (auto& p : pts) p = {lon(rng), lat(rng)};
  const NearestGeoPoint index(pts);
  for (int q = 0; q < 200; ++q) {
    const double x = lon(rng), y = lat(rng);
    double best = 1e30;
    for (const auto& p : pts) best = std::min(best, GreatCircleMetres(x, y, p.lon, p.lat) / 1000);
    EXPECT_NEAR(index.DistanceKm(x, y, 1e9), best, 1e-6 * best + 1e-6);
    EXPECT_LE(index.DistanceKm(x, y, 10.0), 10.0);
  }
}

TEST(AisGeoTest, CoastlineAndPortsFromTheDataDirectory) {
  if (DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const auto coast = ReadShapefileVertices(DataDir() + "/ais/geo/GSHHS_l_coastline.shp");
  EXPECT_GT(coast.size(), 90000u);
  EXPECT_EQ(ReadWorldPortIndex(DataDir() + "/ais/geo/wpi-UpdatedPub150.csv.gz", {"Large"}).size(), 171u);
  EXPECT_EQ(ReadWorldPortIndex(DataDir() + "/ais/geo/wpi-UpdatedPub150.csv.gz", {}).size(), 3768u);
  const Geography geo = Geography::Load(AisOptions(), DataDir());
  const auto map = geo.ForFrame(1.0);
  // Goulet de Brest (the strait, ≈ 1 km wide): within 5 km of a vertex of the low-resolution coast; the middle
  // of the North Atlantic: at the 20 km cap.
  EXPECT_LT(map.distance_to_static(-4.58, 48.345), 5.0);
  EXPECT_DOUBLE_EQ(map.distance_to_static(-35.0, 45.0), 20.0);
  // Rotterdam is a large port: the closest harbour to the Maasvlakte is near.
  EXPECT_LT(map.distance_to_poi(4.05, 51.95), 40.0);
}

// The first `lines` lines of a shipped track file (grouped by MMSI), as a CSV file
// in the test's directory; its path.
std::string SliceOfTracks(const std::string& file, int lines) {
  const std::string text = specht::testing::ReadDecompressed(DataDir() + "/ais/tracks/" + file + ".csv.gz");
  size_t cut = 0;
  for (int i = 0; i < lines; ++i) cut = text.find('\n', cut) + 1;
  const std::string path = TempDir() + "/" + file + "-slice.csv";
  WriteFile(path, text.substr(0, cut));
  return path;
}

TEST(AisDatasetTest, PreparationIsIndependentOfThreadsAndBatches) {
  if (DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string path = SliceOfTracks("brest-dev", 60000);
  const Geography geo = Geography::Load(AisOptions(), DataDir());
  AisPreprocessOptions o;
  AisOptions one, two;
  one.threads = 1, one.batch_vessels = 1;
  two.threads = 2, two.batch_vessels = 7;
  PrepareReport r1, r2;
  const auto a = PrepareDataset({path}, one, o, geo, r1);
  const auto b = PrepareDataset({path}, two, o, geo, r2);
  ASSERT_GT(a.windows.size(), 50u);
  EXPECT_EQ(a.windows.x, b.windows.x);
  EXPECT_EQ(a.windows.y, b.windows.y);
  EXPECT_EQ(a.handcrafted, b.handcrafted);
  EXPECT_EQ(r1.counts, r2.counts);
  // Every feature is normalised into [0, 1].
  for (float x : a.windows.x) ASSERT_TRUE(x >= 0.0f && x <= 1.0f) << x;
}

// The vessels of unknown type: excluded by default; with ais.unlabelled their
// windows come as well, labelled "unlabelled" with class −1, and the labelled
// windows are the same, in the same order.
TEST(AisDatasetTest, VesselsOfUnknownTypeArePreparedOnRequest) {
  if (DataDir().empty()) SPECHT_SKIP() << "no data dir";
  const std::string path = SliceOfTracks("mpa-dev", 40000);  // its first vessels report no ship type
  const Geography geo = Geography::Load(AisOptions(), DataDir());
  const AisPreprocessOptions o;
  AisOptions with;
  with.unlabelled = true;
  PrepareReport r_without, r_with;
  const auto without = PrepareDataset({path}, AisOptions(), o, geo, r_without);
  auto all = PrepareDataset({path}, with, o, geo, r_with);
  EXPECT_GT(r_with.vessels_per_class[kUnlabelled], 10);
  EXPECT_EQ(r_without.vessels_per_class.count(kUnlabelled), 0u);
  EXPECT_LT(r_with.excluded_vessels, r_without.excluded_vessels);
  EXPECT_EQ(r_with.counts["moving"][kUnlabelled] + static_cast<long>(without.windows.size()),
            static_cast<long>(all.windows.size()));
  long unlabelled = 0;
  for (size_t i = 0; i < all.windows.size(); ++i)
    if (all.windows.y[i] < 0) {
      ++unlabelled;
      EXPECT_EQ(all.labels[i], kUnlabelled);
    }
  EXPECT_EQ(unlabelled, r_with.counts["moving"][kUnlabelled]);
  const auto rest = classify::SplitOffUnlabelled(all);
  EXPECT_EQ(static_cast<long>(rest.windows.size()), unlabelled);
  EXPECT_EQ(all.windows.x, without.windows.x);
  EXPECT_EQ(all.windows.y, without.windows.y);
  EXPECT_EQ(all.handcrafted, without.handcrafted);
}

TEST(AisDatasetTest, FoldsAreDisjointByVesselAndStratified) {
  std::vector<std::string> ids;
  std::vector<int> labels;
  for (int v = 0; v < 50; ++v)
    for (int w = 0; w < 1 + v % 4; ++w) ids.push_back(std::to_string(v)), labels.push_back(v % 2);
  const auto folds = classify::FoldsByObject(ids, labels, 5, 1);
  std::map<std::string, std::set<int>> of;
  std::map<int, std::map<int, int>> vessels_per_fold_class;
  std::set<std::string> counted;
  for (size_t i = 0; i < ids.size(); ++i) {
    of[ids[i]].insert(folds[i]);
    if (counted.insert(ids[i]).second) ++vessels_per_fold_class[folds[i]][labels[i]];
  }
  for (const auto& [id, f] : of) EXPECT_EQ(f.size(), 1u) << id;
  for (int f = 0; f < 5; ++f)
    for (int c = 0; c < 2; ++c) EXPECT_EQ(vessels_per_fold_class[f][c], 5) << f << " " << c;
  EXPECT_EQ(classify::FoldsByObject(ids, labels, 5, 1), folds);  // seeded
  EXPECT_NE(classify::FoldsByObject(ids, labels, 5, 2), folds);
}

}  // namespace
}  // namespace specht::ais
