#include "specht/ais/messages.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "specht/core/time.h"

namespace specht::ais {
namespace {

enum class Kind {
  kUnsigned,  // integer
  kSigned,    // two's complement integer
  kBool,
  kText,        // 6-bit characters, to the first '@', trailing spaces trimmed
  kReal,        // unsigned × scale
  kSignedReal,  // signed × scale
  kSpare,       // skipped
};

// One row of the spec's table. `na` is the raw "not available" value (none when
// has_na is false); real fields are raw × scale.
struct Field {
  const char* name;
  int start, width;
  Kind kind;
  double scale = 1.0;
  bool has_na = false;
  int64_t na = 0;
};

constexpr double kMin4 = 1.0 / 600000.0;  // 1/10000 minute, in degrees
constexpr double kMin1 = 1.0 / 600.0;     // 1/10 minute

using K = Kind;
// Class A position report, types 1, 2, 3 (168 bits).
const std::vector<Field> kPositionA = {
    {"status", 38, 4, K::kUnsigned},
    {"rot", 42, 8, K::kSigned, 1, true, -128},
    {"speed", 50, 10, K::kReal, 0.1, true, 1023},
    {"accuracy", 60, 1, K::kBool},
    {"lon", 61, 28, K::kSignedReal, kMin4, true, 181 * 600000},
    {"lat", 89, 27, K::kSignedReal, kMin4, true, 91 * 600000},
    {"course", 116, 12, K::kReal, 0.1, true, 3600},
    {"heading", 128, 9, K::kUnsigned, 1, true, 511},
    {"second", 137, 6, K::kUnsigned, 1, true, 60},
    {"maneuver", 143, 2, K::kUnsigned},
    {"spare", 145, 3, K::kSpare},
    {"raim", 148, 1, K::kBool},
    {"radio", 149, 19, K::kUnsigned},
};
// Base station report (4) and UTC/date response (11), 168 bits.
const std::vector<Field> kBaseStation = {
    {"year", 38, 14, K::kUnsigned},
    {"month", 52, 4, K::kUnsigned},
    {"day", 56, 5, K::kUnsigned},
    {"hour", 61, 5, K::kUnsigned},
    {"minute", 66, 6, K::kUnsigned},
    {"utc_second", 72, 6, K::kUnsigned},
    {"accuracy", 78, 1, K::kBool},
    {"lon", 79, 28, K::kSignedReal, kMin4, true, 181 * 600000},
    {"lat", 107, 27, K::kSignedReal, kMin4, true, 91 * 600000},
    {"epfd", 134, 4, K::kUnsigned},
    {"spare", 138, 10, K::kSpare},
    {"raim", 148, 1, K::kBool},
    {"radio", 149, 19, K::kUnsigned},
};
// Static and voyage related data (5), 424 bits.
const std::vector<Field> kStaticVoyage = {
    {"ais_version", 38, 2, K::kUnsigned}, {"imo", 40, 30, K::kUnsigned},        {"callsign", 70, 42, K::kText},
    {"shipname", 112, 120, K::kText},     {"shiptype", 232, 8, K::kUnsigned},   {"to_bow", 240, 9, K::kUnsigned},
    {"to_stern", 249, 9, K::kUnsigned},   {"to_port", 258, 6, K::kUnsigned},    {"to_starboard", 264, 6, K::kUnsigned},
    {"epfd", 270, 4, K::kUnsigned},       {"eta_month", 274, 4, K::kUnsigned},  {"eta_day", 278, 5, K::kUnsigned},
    {"eta_hour", 283, 5, K::kUnsigned},   {"eta_minute", 288, 6, K::kUnsigned}, {"draught", 294, 8, K::kReal, 0.1},
    {"destination", 302, 120, K::kText},  {"dte", 422, 1, K::kUnsigned},        {"spare", 423, 1, K::kSpare},
};
// Standard SAR aircraft position report (9), 168 bits.
const std::vector<Field> kSarAircraft = {
    {"alt", 38, 12, K::kUnsigned, 1, true, 4095},
    {"speed", 50, 10, K::kUnsigned, 1, true, 1023},
    {"accuracy", 60, 1, K::kBool},
    {"lon", 61, 28, K::kSignedReal, kMin4, true, 181 * 600000},
    {"lat", 89, 27, K::kSignedReal, kMin4, true, 91 * 600000},
    {"course", 116, 12, K::kReal, 0.1, true, 3600},
    {"second", 128, 6, K::kUnsigned, 1, true, 60},
    {"regional", 134, 8, K::kUnsigned},
    {"dte", 142, 1, K::kUnsigned},
    {"spare", 143, 3, K::kSpare},
    {"assigned", 146, 1, K::kBool},
    {"raim", 147, 1, K::kBool},
    {"radio", 148, 20, K::kUnsigned},
};
// Class B position reports: the standard one (18, 168 bits) and the extended one
// (19, 312 bits) share their first fields.
const std::vector<Field> kPositionBCommon = {
    {"reserved", 38, 8, K::kUnsigned},
    {"speed", 46, 10, K::kReal, 0.1, true, 1023},
    {"accuracy", 56, 1, K::kBool},
    {"lon", 57, 28, K::kSignedReal, kMin4, true, 181 * 600000},
    {"lat", 85, 27, K::kSignedReal, kMin4, true, 91 * 600000},
    {"course", 112, 12, K::kReal, 0.1, true, 3600},
    {"heading", 124, 9, K::kUnsigned, 1, true, 511},
    {"second", 133, 6, K::kUnsigned, 1, true, 60},
};
const std::vector<Field> kPositionBStandard = {
    {"regional", 139, 2, K::kUnsigned}, {"cs", 141, 1, K::kBool},   {"display", 142, 1, K::kBool},
    {"dsc", 143, 1, K::kBool},          {"band", 144, 1, K::kBool}, {"msg22", 145, 1, K::kBool},
    {"assigned", 146, 1, K::kBool},     {"raim", 147, 1, K::kBool}, {"radio", 148, 20, K::kUnsigned},
};
const std::vector<Field> kPositionBExtended = {
    {"regional", 139, 4, K::kUnsigned},     {"shipname", 143, 120, K::kText},   {"shiptype", 263, 8, K::kUnsigned},
    {"to_bow", 271, 9, K::kUnsigned},       {"to_stern", 280, 9, K::kUnsigned}, {"to_port", 289, 6, K::kUnsigned},
    {"to_starboard", 295, 6, K::kUnsigned}, {"epfd", 301, 4, K::kUnsigned},     {"raim", 305, 1, K::kBool},
    {"dte", 306, 1, K::kUnsigned},          {"assigned", 307, 1, K::kBool},     {"spare", 308, 4, K::kSpare},
};
// Static data report (24) part A (160 bits) and part B (168 bits). The vendor id is
// gpsd's 42-bit text (3 characters of manufacturer, then the model and serial
// number that M.1371-4 carved out of it and that are given separately).
const std::vector<Field> kStaticA = {
    {"partno", 38, 2, K::kUnsigned},
    {"shipname", 40, 120, K::kText},
};
const std::vector<Field> kStaticB = {
    {"partno", 38, 2, K::kUnsigned}, {"shiptype", 40, 8, K::kUnsigned}, {"vendorid", 48, 42, K::kText},
    {"model", 66, 4, K::kUnsigned},  {"serial", 70, 20, K::kUnsigned},  {"callsign", 90, 42, K::kText},
};
const std::vector<Field> kStaticBDimensions = {
    {"to_bow", 132, 9, K::kUnsigned},
    {"to_stern", 141, 9, K::kUnsigned},
    {"to_port", 150, 6, K::kUnsigned},
    {"to_starboard", 156, 6, K::kUnsigned},
};
const std::vector<Field> kStaticBMothership = {
    {"mothership_mmsi", 132, 30, K::kUnsigned},
};
// Long-range AIS broadcast (27), 96 bits.
const std::vector<Field> kLongRange = {
    {"accuracy", 38, 1, K::kBool},
    {"raim", 39, 1, K::kBool},
    {"status", 40, 4, K::kUnsigned},
    {"lon", 44, 18, K::kSignedReal, kMin1, true, 181 * 600},
    {"lat", 62, 17, K::kSignedReal, kMin1, true, 91 * 600},
    {"speed", 79, 6, K::kUnsigned, 1, true, 63},
    {"course", 85, 9, K::kUnsigned, 1, true, 511},
    {"gnss", 94, 1, K::kBool},
    {"spare", 95, 1, K::kSpare},
};

// Bits a table needs: up to the first bit of its last field. Trailing spare bits
// are often missing, and the last field may be cut short (senders that drop fill
// bits); it is then read from the bits there are, as gpsd does.
int RequiredBits(const std::vector<Field>& table) {
  int end = 0;
  for (const auto& f : table)
    if (f.kind != K::kSpare) end = std::max(end, f.start + 1);
  return end;
}

uint64_t Bits(const std::vector<uint8_t>& bits, int start, int width) {
  uint64_t v = 0;
  for (int i = 0; i < width; ++i) v = (v << 1) | bits[start + i];
  return v;
}

int64_t SignedBits(const std::vector<uint8_t>& bits, int start, int width) {
  const uint64_t v = Bits(bits, start, width);
  return (v >> (width - 1)) ? static_cast<int64_t>(v) - (int64_t{1} << width) : static_cast<int64_t>(v);
}

std::string Text(const std::vector<uint8_t>& bits, int start, int width) {
  std::string s;
  for (int i = 0; i + 6 <= width; i += 6) {
    const int v = static_cast<int>(Bits(bits, start + i, 6));
    const char c = static_cast<char>(v < 32 ? v + 64 : v);
    if (c == '@') break;
    s.push_back(c);
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

Value Decode(const std::vector<uint8_t>& bits, Field f) {
  f.width = std::min(f.width, static_cast<int>(bits.size()) - f.start);
  if (f.width <= 0) return {};
  switch (f.kind) {
    case K::kBool:
      return Bits(bits, f.start, 1) != 0;
    case K::kText:
      return Text(bits, f.start, f.width);
    default:
      break;
  }
  const int64_t raw = f.kind == K::kSigned || f.kind == K::kSignedReal
                          ? SignedBits(bits, f.start, f.width)
                          : static_cast<int64_t>(Bits(bits, f.start, f.width));
  if (f.has_na && raw == f.na) return {};
  if (f.kind == K::kReal || f.kind == K::kSignedReal) return static_cast<double>(raw) * f.scale;
  return raw;
}

void DecodeTable(const std::vector<uint8_t>& bits, const std::vector<Field>& table, Message& m) {
  for (const auto& f : table)
    if (f.kind != K::kSpare) m.fields.emplace_back(f.name, Decode(bits, f));
}

std::string Format(const char* fmt, int64_t a, int64_t b, int64_t c, int64_t d, int64_t e = 0, int64_t f = 0) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, static_cast<long long>(a), static_cast<long long>(b), static_cast<long long>(c),
                static_cast<long long>(d), static_cast<long long>(e), static_cast<long long>(f));
  return buf;
}

int64_t IntOr(const Message& m, const char* name, int64_t fallback = 0) {
  const auto v = m.Number(name);
  return v ? static_cast<int64_t>(*v) : fallback;
}

// Type 4/11: "timestamp" as gpsd writes it, and time_s when the date is valid
// (year 0, month 0, day 0, hour 24, minute 60, second 60 mean not available).
void AddUtcTime(Message& m) {
  const int64_t y = IntOr(m, "year"), mo = IntOr(m, "month"), d = IntOr(m, "day"), h = IntOr(m, "hour"),
                mi = IntOr(m, "minute"), s = IntOr(m, "utc_second");
  m.Set("timestamp", Format("%04lld-%02lld-%02lldT%02lld:%02lld:%02lldZ", y, mo, d, h, mi, s));
  const bool valid = y > 0 && mo >= 1 && mo <= 12 && d >= 1 && d <= 31 && h < 24 && mi < 60 && s < 60;
  m.Set("time_s", valid ? Value(static_cast<double>(UnixSecondsFromUtc(y, mo, d, h, mi, s))) : Value());
}

void AddEta(Message& m) {
  m.Set("eta", Format("%02lld-%02lldT%02lld:%02lldZ", IntOr(m, "eta_month"), IntOr(m, "eta_day"), IntOr(m, "eta_hour"),
                      IntOr(m, "eta_minute")));
}

// ROT_AIS = 4.733 √(ROT °/min), signed; ±127 means turning faster than 5°/30 s
// without a figure, so only |raw| ≤ 126 gives a rate.
void AddTurn(Message& m) {
  const auto raw = m.Number("rot");
  if (!raw || std::abs(*raw) >= 127) {
    m.Set("turn", Value());
    return;
  }
  const double r = *raw / 4.733;
  m.Set("turn", std::copysign(r * r, *raw));
}

}  // namespace

const Value* Message::Find(const std::string& name) const {
  for (const auto& [n, v] : fields)
    if (n == name) return &v;
  return nullptr;
}

std::optional<double> Message::Number(const std::string& name) const {
  const Value* v = Find(name);
  if (v == nullptr) return std::nullopt;
  if (const auto* b = std::get_if<bool>(v)) return *b ? 1.0 : 0.0;
  if (const auto* i = std::get_if<int64_t>(v)) return static_cast<double>(*i);
  if (const auto* d = std::get_if<double>(v)) return *d;
  return std::nullopt;
}

std::string Message::Text(const std::string& name) const {
  const Value* v = Find(name);
  const auto* s = v == nullptr ? nullptr : std::get_if<std::string>(v);
  return s == nullptr ? "" : *s;
}

void Message::Set(const std::string& name, Value v) {
  for (auto& [n, old] : fields)
    if (n == name) {
      old = std::move(v);
      return;
    }
  fields.emplace_back(name, std::move(v));
}

nlohmann::json Message::ToJson() const {
  nlohmann::json j = {{"class", "AIS"}, {"type", type}, {"repeat", repeat}, {"mmsi", mmsi}};
  for (const auto& [name, v] : fields) {
    std::visit(
        [&j, &n = name](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, std::monostate>)
            j[n] = nullptr;
          else
            j[n] = x;
        },
        v);
  }
  if (time_s) j["rx_time"] = *time_s;
  return j;
}

std::string TurnText(int raw) {
  if (raw == -128) return "n/a";
  if (raw == 127) return "fastright";
  if (raw == -127) return "fastleft";
  const double r = raw / 4.733;
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", std::copysign(r * r, static_cast<double>(raw)));
  return buf;
}

bool DecodeMessage(const RawMessage& raw, Message& m, std::string& reason) {
  const auto& b = raw.bits;
  m = Message();
  m.time_s = raw.time_s;
  m.source = raw.source;
  m.channel = raw.channel;
  m.line = raw.line;
  if (b.size() < 38) {
    reason = "message shorter than its header (38 bits)";
    return false;
  }
  m.type = static_cast<int>(Bits(b, 0, 6));
  m.repeat = static_cast<int>(Bits(b, 6, 2));
  m.mmsi = static_cast<int64_t>(Bits(b, 8, 30));
  if (m.type < 1 || m.type > 27) {
    reason = "unknown message type " + std::to_string(m.type);
    return false;
  }
  // The message's field tables in bit order. Assigned as whole vectors (moved): GCC 12
  // warns of a null memmove in copying an initializer list into an empty one.
  using Tables = std::vector<const std::vector<Field>*>;
  Tables tables;
  switch (m.type) {
    case 1:
    case 2:
    case 3:
      tables = Tables{&kPositionA};
      break;
    case 4:
    case 11:
      tables = Tables{&kBaseStation};
      break;
    case 5:
      tables = Tables{&kStaticVoyage};
      break;
    case 9:
      tables = Tables{&kSarAircraft};
      break;
    case 18:
      tables = Tables{&kPositionBCommon, &kPositionBStandard};
      break;
    case 19:
      tables = Tables{&kPositionBCommon, &kPositionBExtended};
      break;
    case 27:
      tables = Tables{&kLongRange};
      break;
    case 24: {
      if (b.size() < 40) {
        reason = "type 24 shorter than its part number";
        return false;
      }
      const int part = static_cast<int>(Bits(b, 38, 2));
      if (part > 1) {
        reason = "type 24 with reserved part number " + std::to_string(part);
        return false;
      }
      // Auxiliary craft (MMSI 98xxxyyyy) carry their mother ship's MMSI in place
      // of the dimensions.
      const bool auxiliary = m.mmsi / 10000000 == 98;
      tables = part == 0 ? Tables{&kStaticA} : Tables{&kStaticB, auxiliary ? &kStaticBMothership : &kStaticBDimensions};
      break;
    }
    default:
      return m.complete = false, true;  // header only
  }
  for (const auto* table : tables)
    if (static_cast<int>(b.size()) < RequiredBits(*table)) {
      reason = "type " + std::to_string(m.type) + " shorter than its fields (" + std::to_string(RequiredBits(*table)) +
               " bits)";
      return false;
    }
  for (const auto* table : tables) DecodeTable(b, *table, m);
  if (m.type == 1 || m.type == 2 || m.type == 3) AddTurn(m);
  if (m.type == 4 || m.type == 11) AddUtcTime(m);
  if (m.type == 5) AddEta(m);
  m.complete = true;
  return true;
}

std::optional<Message> StaticDataJoiner::Feed(const Message& m) {
  if (m.type != 24 || !m.complete) return m;
  const auto held = std::find_if(held_.begin(), held_.end(), [&](const Message& a) { return a.mmsi == m.mmsi; });
  if (m.Number("partno").value_or(0) == 0) {
    if (held != held_.end()) held_.erase(held);
    held_.push_back(m);
    if (held_.size() > 4096) held_.erase(held_.begin());
    return std::nullopt;
  }
  if (held == held_.end()) {
    ++lone_part_b_;
    return std::nullopt;
  }
  Message joined = m;
  joined.Set("shipname", held->fields.back().second);
  held_.erase(held);
  return joined;
}

}  // namespace specht::ais
