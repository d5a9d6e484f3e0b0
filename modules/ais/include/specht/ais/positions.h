// specht/ais/positions.h: tabular AIS position reports, vessel by vessel.
//
// Layouts, detected from the header:
//   specht     mmsi,time,lon,lat[,sog,cog][,ship_type]   (epoch s, degrees, knots;
//              the data directory's ais/tracks files and `specht ais decode` output)
//   noaa       MarineCadastre: MMSI,BaseDateTime,LAT,LON,SOG,COG,…,VesselType,…
//              (ISO time, UTC; VesselType an ITU ship type code)
//   dma        Danish Maritime Authority: # Timestamp,Type of mobile,MMSI,Latitude,
//              Longitude,…,SOG,COG,…,Ship type,… (dd/mm/yyyy HH:MM:SS; ship type as
//              text, mapped to its ITU code)
// Rows are grouped by MMSI (a vessel's rows together, as the shipped files and
// decode's output are); a vessel that reappears later is an InputError naming the
// line, with the sort command that fixes it. Within a vessel, rows are sorted by
// time and exact duplicates dropped. Speed and course, where absent, are derived
// from consecutive positions (great-circle distance and initial bearing).
// Unparseable rows are skipped and counted by reason (never fatal).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace specht::ais {

struct PositionReport {
  double t_s = 0, lon = 0, lat = 0;
  double sog_kn = -1, cog_deg = -1;  // negative: not reported (derived later)
};

struct Vessel {
  int64_t mmsi = 0;
  int ship_type = -1;  // ITU code (the most frequent one reported), −1 unknown
  std::vector<PositionReport> reports;
};

// The five classes of the vessel paper, from ITU ship type codes: Cargo-Tanker
// 70–89, Fishing 30, Passenger 60–69, Pleasure Craft 36–37, Tug 31, 32, 52; "" else.
std::string ClassOfShipType(int code);
const std::vector<std::string>& VesselClasses();
// The flag state of a vessel: the Maritime Identification Digits of its MMSI
// (ITU-R M.585: MIDXXXXXX for a ship station, 8MIDXXXXX for a handheld, 98MIDXXXX
// for a craft associated with a parent ship), 201–775; 0 for numbers that are not
// a vessel's (coast stations 00MID…, groups 0MID…, aids to navigation 99MID…, SAR
// aircraft 111MID…, AIS-SART/MOB/EPIRB 97…) or carry no valid MID.
int FlagMid(int64_t mmsi);
// DMA ship type text ("Cargo", "Towing long/wide", …) to its ITU code, −1 unknown.
int ShipTypeOfDmaText(const std::string& text);

// Great-circle distance (m, spherical Earth R = 6 371 008.8 m) and initial bearing
// (degrees clockwise from north).
double GreatCircleMetres(double lon1, double lat1, double lon2, double lat2);
double InitialBearingDeg(double lon1, double lat1, double lon2, double lat2);
// Fills sog_kn/cog_deg where negative from the neighbouring reports.
void DeriveSpeedAndCourse(std::vector<PositionReport>& reports);

struct PositionStats {
  int64_t rows = 0, vessels = 0, duplicates = 0;
  std::map<std::string, int64_t> skipped;  // reason → rows
  std::string first_problem;               // "file:line: reason" of the first skip
};

class VesselReader {
 public:
  // InputError naming the file when it cannot be opened or the header is not one
  // of the known layouts.
  explicit VesselReader(const std::string& path);
  ~VesselReader();
  // The next vessel; false at the end.
  bool Next(Vessel& v);
  const std::string& layout() const;
  const PositionStats& stats() const;
  double Fraction() const;  // of the file read, for progress

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace specht::ais
