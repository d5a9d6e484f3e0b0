#include "specht/ais/positions.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "specht/ais/geo.h"
#include "specht/core/csv.h"
#include "specht/core/error.h"
#include "specht/core/time.h"
#include "specht/io/line_reader.h"

namespace specht::ais {
namespace {

bool ParseDouble(const std::string& s, double& out) {
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}

bool ParseInt64(const std::string& s, int64_t& out) {
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// Fixed-width digits at s[at, at+n).
bool Digits(const std::string& s, size_t at, size_t n, int64_t& out) {
  if (at + n > s.size()) return false;
  out = 0;
  for (size_t i = at; i < at + n; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    out = out * 10 + (s[i] - '0');
  }
  return true;
}

// A UTC time with fixed-position fields: a 4-digit year at `y`, 2-digit month,
// day, hour, minute, second at the other offsets.
bool ParseFixedTime(const std::string& s, size_t y, size_t mo, size_t d, size_t h, size_t mi, size_t sec, double& t) {
  int64_t year, month, day, hour, minute, second;
  if (!Digits(s, y, 4, year) || !Digits(s, mo, 2, month) || !Digits(s, d, 2, day) || !Digits(s, h, 2, hour) ||
      !Digits(s, mi, 2, minute) || !Digits(s, sec, 2, second) || month < 1 || month > 12 || day < 1 || day > 31)
    return false;
  t = static_cast<double>(UnixSecondsFromUtc(year, month, day, hour, minute, second));
  return true;
}

// "2020-01-01T00:00:00" or "2020-01-01 00:00:00" (NOAA).
bool ParseIsoTime(const std::string& s, double& t) { return ParseFixedTime(s, 0, 5, 8, 11, 14, 17, t); }
// "31/12/2023 23:59:59" (DMA).
bool ParseDmaTime(const std::string& s, double& t) { return ParseFixedTime(s, 6, 3, 0, 11, 14, 17, t); }

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Column indices of one layout.
struct Columns {
  std::string layout;
  int mmsi = -1, time = -1, lon = -1, lat = -1, sog = -1, cog = -1, ship_type = -1;
  bool dma_time = false, iso_time = false, ship_type_text = false;
};

Columns DetectLayout(const std::vector<std::string>& header, const std::string& path) {
  std::map<std::string, int> at;
  for (size_t i = 0; i < header.size(); ++i) at[Lower(header[i])] = static_cast<int>(i);
  auto col = [&](const char* name) { return at.count(name) ? at[name] : -1; };
  Columns c;
  if (col("mmsi") >= 0 && col("time") >= 0 && col("lon") >= 0 && col("lat") >= 0) {
    c = {"specht", col("mmsi"), col("time"), col("lon"), col("lat"), col("sog"), col("cog"), col("ship_type")};
  } else if (col("mmsi") >= 0 && col("basedatetime") >= 0) {
    c = {"noaa", col("mmsi"), col("basedatetime"), col("lon"), col("lat"), col("sog"), col("cog"), col("vesseltype")};
    c.iso_time = true;
  } else if (col("mmsi") >= 0 && col("# timestamp") >= 0) {
    c = {"dma",           col("mmsi"), col("# timestamp"), col("longitude"),
         col("latitude"), col("sog"),  col("cog"),         col("ship type")};
    c.dma_time = c.ship_type_text = true;
  } else {
    throw InputError(path +
                     ":1: header matches no known AIS layout (need mmsi,time,lon,lat[,ship_type]; "
                     "NOAA MarineCadastre MMSI,BaseDateTime,LAT,LON,…; or DMA # Timestamp,…,MMSI,…)");
  }
  if (c.lon < 0 || c.lat < 0) throw InputError(path + ":1: " + c.layout + " layout without longitude/latitude columns");
  return c;
}

void SortAndDeduplicate(Vessel& v, PositionStats& stats) {
  auto& r = v.reports;
  std::stable_sort(r.begin(), r.end(), [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
  const size_t before = r.size();
  r.erase(std::unique(r.begin(), r.end(),
                      [](const auto& a, const auto& b) { return a.t_s == b.t_s && a.lon == b.lon && a.lat == b.lat; }),
          r.end());
  stats.duplicates += static_cast<int64_t>(before - r.size());
}

}  // namespace

const std::vector<std::string>& VesselClasses() {
  static const std::vector<std::string> classes = {"Cargo-Tanker", "Fishing", "Passenger", "Pleasure Craft", "Tug"};
  return classes;
}

std::string ClassOfShipType(int t) {
  if (t >= 70 && t <= 89) return "Cargo-Tanker";
  if (t == 30) return "Fishing";
  if (t >= 60 && t <= 69) return "Passenger";
  if (t == 36 || t == 37) return "Pleasure Craft";
  if (t == 31 || t == 32 || t == 52) return "Tug";
  return "";
}

int FlagMid(int64_t mmsi) {
  if (mmsi < 100000000 || mmsi > 999999999) return 0;  // not nine digits, or a leading 0 (groups, coast stations)
  const int lead = static_cast<int>(mmsi / 100000000), lead2 = static_cast<int>(mmsi / 10000000);
  int mid = 0;
  if (lead >= 2 && lead <= 7)
    mid = static_cast<int>(mmsi / 1000000);  // MIDXXXXXX
  else if (lead == 8)
    mid = static_cast<int>(mmsi / 100000 % 1000);  // 8MIDXXXXX
  else if (lead2 == 98)
    mid = static_cast<int>(mmsi / 10000 % 1000);  // 98MIDXXXX
  return mid >= 201 && mid <= 775 ? mid : 0;
}

int ShipTypeOfDmaText(const std::string& text) {
  static const std::map<std::string, int> codes = {{"wig", 20},
                                                   {"fishing", 30},
                                                   {"towing", 31},
                                                   {"towing long/wide", 32},
                                                   {"dredging", 33},
                                                   {"diving", 34},
                                                   {"military", 35},
                                                   {"sailing", 36},
                                                   {"pleasure", 37},
                                                   {"hsc", 40},
                                                   {"pilot", 50},
                                                   {"sar", 51},
                                                   {"tug", 52},
                                                   {"port tender", 53},
                                                   {"anti-pollution", 54},
                                                   {"law enforcement", 55},
                                                   {"medical", 58},
                                                   {"not party to conflict", 59},
                                                   {"passenger", 60},
                                                   {"cargo", 70},
                                                   {"tanker", 80},
                                                   {"other", 90}};
  const auto it = codes.find(Lower(text));
  return it == codes.end() ? -1 : it->second;
}

double GreatCircleMetres(double lon1, double lat1, double lon2, double lat2) {
  // Haversine: well conditioned for the short steps between reports.
  const double dlat = (lat2 - lat1) * kDegree, dlon = (lon2 - lon1) * kDegree;
  const double a = std::sin(dlat / 2) * std::sin(dlat / 2) +
                   std::cos(lat1 * kDegree) * std::cos(lat2 * kDegree) * std::sin(dlon / 2) * std::sin(dlon / 2);
  return 2 * kEarthRadiusM * std::asin(std::min(1.0, std::sqrt(a)));
}

double InitialBearingDeg(double lon1, double lat1, double lon2, double lat2) {
  const double p1 = lat1 * kDegree, p2 = lat2 * kDegree, dl = (lon2 - lon1) * kDegree;
  const double b =
      std::atan2(std::sin(dl) * std::cos(p2), std::cos(p1) * std::sin(p2) - std::sin(p1) * std::cos(p2) * std::cos(dl));
  return std::fmod(b / kDegree + 360.0, 360.0);
}

void DeriveSpeedAndCourse(std::vector<PositionReport>& r) {
  for (size_t i = 0; i < r.size(); ++i) {
    // From the previous report, or to the next one for the first.
    const size_t a = i > 0 ? i - 1 : i, b = i > 0 ? i : std::min(i + 1, r.size() - 1);
    const double dt = r[b].t_s - r[a].t_s;
    if (r[i].sog_kn < 0)
      r[i].sog_kn = dt > 0 ? GreatCircleMetres(r[a].lon, r[a].lat, r[b].lon, r[b].lat) / dt / kKnot : 0;
    if (r[i].cog_deg < 0) r[i].cog_deg = a != b ? InitialBearingDeg(r[a].lon, r[a].lat, r[b].lon, r[b].lat) : 0;
  }
}

struct VesselReader::Impl {
  std::string path;
  io::LineReader lines;
  uint64_t size = 0;
  Columns c;
  PositionStats stats;
  std::vector<std::string> cells;
  std::set<int64_t> finished;
  bool have_pending = false, done = false;
  int64_t pending_mmsi = 0;
  PositionReport pending;
  int pending_type = -1;

  explicit Impl(const std::string& p) : path(p), lines(p) {
    std::error_code ec;
    size = std::filesystem::file_size(p, ec);
    std::string line;
    while (lines.Next(line))
      if (!line.empty() && line.find_first_not_of(" \t\r") != std::string::npos) break;
    if (line.empty()) throw InputError(path + ": empty file (no header)");
    SplitCsv(line, cells);
    c = DetectLayout(cells, path);
  }

  void Skip(const std::string& reason) {
    ++stats.skipped[reason];
    if (stats.first_problem.empty()) stats.first_problem = path + ":" + std::to_string(lines.number()) + ": " + reason;
  }

  // Parses the next good row into (mmsi, report, ship type); false at the end.
  bool NextRow(int64_t& mmsi, PositionReport& r, int& ship_type) {
    std::string line;
    while (lines.Next(line)) {
      if (line.empty()) continue;
      ++stats.rows;
      SplitCsv(line, cells);
      const int n = static_cast<int>(cells.size());
      auto cell = [&](int i) -> const std::string& {
        static const std::string empty;
        return i >= 0 && i < n ? cells[i] : empty;
      };
      if (!ParseInt64(cell(c.mmsi), mmsi)) {
        Skip("bad mmsi");
        continue;
      }
      bool time_ok = c.iso_time   ? ParseIsoTime(cell(c.time), r.t_s)
                     : c.dma_time ? ParseDmaTime(cell(c.time), r.t_s)
                                  : ParseDouble(cell(c.time), r.t_s);
      if (!time_ok) {
        Skip("bad time");
        continue;
      }
      if (!ParseDouble(cell(c.lon), r.lon) || !ParseDouble(cell(c.lat), r.lat) || std::abs(r.lon) > 180 ||
          std::abs(r.lat) > 90) {
        Skip("bad or unavailable position");
        continue;
      }
      if (!ParseDouble(cell(c.sog), r.sog_kn) || r.sog_kn < 0 || r.sog_kn >= 102.2) r.sog_kn = -1;
      if (!ParseDouble(cell(c.cog), r.cog_deg) || r.cog_deg < 0 || r.cog_deg >= 360) r.cog_deg = -1;
      int64_t type = -1;
      if (c.ship_type_text)
        type = ShipTypeOfDmaText(cell(c.ship_type));
      else if (!ParseInt64(cell(c.ship_type), type))
        type = -1;
      ship_type = static_cast<int>(type);
      return true;
    }
    return false;
  }
};

VesselReader::VesselReader(const std::string& path) : impl_(std::make_unique<Impl>(path)) {}
VesselReader::~VesselReader() = default;
const std::string& VesselReader::layout() const { return impl_->c.layout; }
const PositionStats& VesselReader::stats() const { return impl_->stats; }
double VesselReader::Fraction() const { return impl_->lines.Fraction(impl_->size); }

bool VesselReader::Next(Vessel& v) {
  Impl& s = *impl_;
  v = Vessel();
  if (!s.have_pending) {
    if (s.done || !s.NextRow(s.pending_mmsi, s.pending, s.pending_type)) {
      s.done = true;
      return false;
    }
    s.have_pending = true;
  }
  v.mmsi = s.pending_mmsi;
  if (s.finished.count(v.mmsi))
    throw InputError(s.path + ":" + std::to_string(s.lines.number()) + ": MMSI " + std::to_string(v.mmsi) +
                     " appears again after other vessels; rows must be grouped by MMSI (e.g. "
                     "`(head -1 f.csv; tail -n +2 f.csv | sort -t, -k1,1n -k2,2) > grouped.csv`)");
  std::map<int, int> type_votes;
  auto add = [&](const PositionReport& r, int type) {
    v.reports.push_back(r);
    if (type >= 0) ++type_votes[type];
  };
  add(s.pending, s.pending_type);
  s.have_pending = false;
  int64_t mmsi;
  PositionReport r;
  int type;
  while (s.NextRow(mmsi, r, type)) {
    if (mmsi != v.mmsi) {
      s.pending_mmsi = mmsi, s.pending = r, s.pending_type = type, s.have_pending = true;
      break;
    }
    add(r, type);
  }
  if (!s.have_pending) s.done = true;
  s.finished.insert(v.mmsi);
  int best = 0;
  for (const auto& [t, votes] : type_votes)
    if (votes > best) best = votes, v.ship_type = t;
  SortAndDeduplicate(v, s.stats);
  DeriveSpeedAndCourse(v.reports);
  ++s.stats.vessels;
  return true;
}

}  // namespace specht::ais
