// specht/ais/messages.h: AIS message bits to named fields (ITU-R M.1371-5, Annex 8),
// table-driven: each supported type is a list of fields (name, first bit, width,
// kind, scale, "not available" value) written in messages.cpp as the spec's tables.
//
// Supported in full: 1, 2, 3 (class A position), 4, 11 (base station / UTC report),
// 5 (static and voyage data), 9 (SAR aircraft), 18, 19 (class B position, extended),
// 24 A/B (class B static data), 27 (long-range position). Other types decode their
// header (type, repeat, mmsi) only and are counted as such.
//
// Field names and units follow gpsd's JSON (so its decoder output can be compared
// field by field): lon/lat in degrees, speed in knots, course and heading in degrees,
// turn in degrees per minute, draught in metres, to_bow … in metres. A "not
// available" value (lon 181, speed 102.3, heading 511, …) is null.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "specht/ais/nmea.h"

namespace specht::ais {

// null (not available), bool, integer, real, text.
using Value = std::variant<std::monostate, bool, int64_t, double, std::string>;

struct Message {
  int type = 0, repeat = 0;
  int64_t mmsi = 0;
  bool complete = false;                              // every field of the type decoded (false: header only)
  std::vector<std::pair<std::string, Value>> fields;  // in message order
  // From the sentence layer.
  std::optional<double> time_s;
  std::string source;
  char channel = 0;
  int64_t line = 0;

  const Value* Find(const std::string& name) const;
  // A numeric field (bool, integer or real) as double; nullopt when absent or null.
  std::optional<double> Number(const std::string& name) const;
  std::string Text(const std::string& name) const;  // "" when absent or null
  void Set(const std::string& name, Value v);       // replaces or appends
  // gpsd-style object: class "AIS", type, repeat, mmsi, then the fields.
  nlohmann::json ToJson() const;
};

// Decodes one message. Returns false with `reason` when the bit string is too short
// for its type (and part, for type 24) or the type is 0 / unknown beyond 27.
bool DecodeMessage(const RawMessage& raw, Message& out, std::string& reason);

// gpsd's presentation of the rate of turn: "n/a", "fastleft", "fastright" or the
// rate in °/min with two decimals ("0.00"); from the raw field value.
std::string TurnText(int raw);

// Class B static data comes in two messages (24 A: name; 24 B: type, vendor, call
// sign, dimensions). This joins them by MMSI, as gpsd does: part A is held, part B
// of the same vessel is emitted merged with it; a part B without a held part A is
// not emitted (the decoder counts it).
class StaticDataJoiner {
 public:
  // Returns the message to emit, if any (every message other than type 24 passes).
  std::optional<Message> Feed(const Message& m);
  int64_t lone_part_b() const { return lone_part_b_; }

 private:
  std::vector<Message> held_;  // part A per MMSI, most recent last (bounded)
  int64_t lone_part_b_ = 0;
};

}  // namespace specht::ais
