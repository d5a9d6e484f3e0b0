#include "specht/ais/geo.h"

#include <shapefil.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nanoflann.hpp>

#include "specht/core/csv.h"
#include "specht/core/error.h"
#include "specht/io/line_reader.h"

namespace specht::ais {
namespace {

struct Unit {
  double x, y, z;
};

Unit ToUnit(double lon, double lat) {
  const double cl = std::cos(lat * kDegree);
  return {cl * std::cos(lon * kDegree), cl * std::sin(lon * kDegree), std::sin(lat * kDegree)};
}

struct Cloud {
  std::vector<Unit> pts;
  size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(size_t i, size_t d) const { return d == 0 ? pts[i].x : d == 1 ? pts[i].y : pts[i].z; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, unsigned int>;

}  // namespace

struct NearestGeoPoint::Index {
  Cloud cloud;
  std::unique_ptr<Tree> tree;
};

NearestGeoPoint::NearestGeoPoint(std::vector<GeoPoint> points) : index_(std::make_unique<Index>()) {
  for (const auto& p : points) index_->cloud.pts.push_back(ToUnit(p.lon, p.lat));
  if (!index_->cloud.pts.empty()) {
    index_->tree = std::make_unique<Tree>(3, index_->cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    index_->tree->buildIndex();
  }
}

NearestGeoPoint::~NearestGeoPoint() = default;
NearestGeoPoint::NearestGeoPoint(NearestGeoPoint&&) noexcept = default;
size_t NearestGeoPoint::size() const { return index_->cloud.pts.size(); }

double NearestGeoPoint::DistanceKm(double lon, double lat, double cap_km) const {
  if (!index_->tree) return cap_km;
  const Unit q = ToUnit(lon, lat);
  const double query[3] = {q.x, q.y, q.z};
  unsigned int index = 0;
  double chord_sq = 0;
  index_->tree->knnSearch(query, 1, &index, &chord_sq);
  const double theta = 2 * std::asin(std::min(1.0, std::sqrt(chord_sq) / 2));
  return std::min(cap_km, theta * kEarthRadiusM / 1000.0);
}

std::vector<GeoPoint> ReadShapefileVertices(const std::string& shp_path) {
  SHPHandle h = SHPOpen(shp_path.c_str(), "rb");
  if (h == nullptr) throw InputError(shp_path + ": cannot open as an ESRI shapefile (.shp/.shx)");
  int count = 0, type = 0;
  SHPGetInfo(h, &count, &type, nullptr, nullptr);
  std::vector<GeoPoint> out;
  for (int i = 0; i < count; ++i) {
    SHPObject* o = SHPReadObject(h, i);
    if (o == nullptr) {
      SHPClose(h);
      throw InputError(shp_path + ": shape " + std::to_string(i) + " of " + std::to_string(count) +
                       " cannot be read (truncated or corrupt file)");
    }
    for (int v = 0; v < o->nVertices; ++v)
      if (std::abs(o->padfX[v]) <= 360 && std::abs(o->padfY[v]) <= 90)
        out.push_back({o->padfX[v] > 180 ? o->padfX[v] - 360 : o->padfX[v], o->padfY[v]});
    SHPDestroyObject(o);
  }
  SHPClose(h);
  return out;
}

std::vector<GeoPoint> ReadWorldPortIndex(const std::string& csv_path, const std::vector<std::string>& sizes) {
  io::LineReader lines(csv_path);
  std::string line;
  std::vector<std::string> cells;
  if (!lines.Next(line)) throw InputError(csv_path + ": empty file");
  SplitCsv(line, cells);
  auto column = [&](const char* name) {
    const auto it = std::find(cells.begin(), cells.end(), name);
    if (it == cells.end()) throw InputError(csv_path + ":1: no column \"" + name + "\"");
    return static_cast<size_t>(it - cells.begin());
  };
  const size_t lat = column("Latitude"), lon = column("Longitude"), size = column("Harbor Size");
  std::vector<GeoPoint> out;
  while (lines.Next(line)) {
    if (line.empty()) continue;
    SplitCsv(line, cells);
    const auto where = csv_path + ":" + std::to_string(lines.number());
    if (cells.size() <= std::max({lat, lon, size})) throw InputError(where + ": row has too few cells");
    if (!sizes.empty() && std::find(sizes.begin(), sizes.end(), cells[size]) == sizes.end()) continue;
    char* end = nullptr;
    GeoPoint p;
    p.lat = std::strtod(cells[lat].c_str(), &end);
    const bool lat_ok = end != cells[lat].c_str() && *end == '\0';
    p.lon = std::strtod(cells[lon].c_str(), &end);
    const bool lon_ok = end != cells[lon].c_str() && *end == '\0';
    if (!lat_ok || !lon_ok || std::abs(p.lat) > 90 || std::abs(p.lon) > 180)
      throw InputError(where + ": bad Latitude/Longitude \"" + cells[lat] + "\", \"" + cells[lon] + "\"");
    out.push_back(p);
  }
  return out;
}

}  // namespace specht::ais
