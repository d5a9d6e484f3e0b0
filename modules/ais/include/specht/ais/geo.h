// specht/ais/geo.h: the vessel paper's geographic features — distance to the coast
// and to the closest harbour — by nearest-neighbour search over great-circle
// distances.
//
// Points are stored as unit vectors in a k-d tree (nanoflann); the chord length c
// between unit vectors is monotonic in the great-circle angle θ = 2 asin(c / 2), so
// the nearest by chord is the nearest on the sphere, and the distance is R θ.
// As in the paper, the coastline is represented by its vertices ("edge points") of
// the low-resolution GSHHG shorelines, read with shapelib.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace specht::ais {

// Spherical Earth with the mean radius (IUGG), and the knot, for every AIS figure.
constexpr double kEarthRadiusM = 6371008.8;
constexpr double kDegree = M_PI / 180.0;                      // radians
constexpr double kMetresPerDegree = kEarthRadiusM * kDegree;  // along a meridian
constexpr double kKnot = 1852.0 / 3600.0;                     // m/s

struct GeoPoint {
  double lon = 0, lat = 0;
};

class NearestGeoPoint {
 public:
  explicit NearestGeoPoint(std::vector<GeoPoint> points);
  ~NearestGeoPoint();
  NearestGeoPoint(NearestGeoPoint&&) noexcept;
  // Great-circle distance (km) to the nearest point, capped at cap_km (also when
  // there are no points). Thread-safe.
  double DistanceKm(double lon, double lat, double cap_km) const;
  size_t size() const;

 private:
  struct Index;
  std::unique_ptr<Index> index_;
};

// Every vertex of every shape in an ESRI shapefile (.shp with its .shx/.dbf).
// InputError naming the file when shapelib cannot open it.
std::vector<GeoPoint> ReadShapefileVertices(const std::string& shp_path);

// Ports of the World Port Index CSV (gzip or plain) whose "Harbor Size" is in
// `sizes` (empty: all). InputError naming the file and line on a missing column or
// a bad coordinate.
std::vector<GeoPoint> ReadWorldPortIndex(const std::string& csv_path, const std::vector<std::string>& sizes);

}  // namespace specht::ais
