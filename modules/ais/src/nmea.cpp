#include "specht/ais/nmea.h"

#include <charconv>
#include <cstdlib>

namespace specht::ais {
namespace {

// Splits on ',' (no quoting in NMEA).
std::vector<std::string_view> SplitFields(std::string_view s) {
  std::vector<std::string_view> out;
  size_t start = 0;
  for (size_t i = 0; i <= s.size(); ++i)
    if (i == s.size() || s[i] == ',') {
      out.push_back(s.substr(start, i - start));
      start = i + 1;
    }
  return out;
}

bool ParseInt(std::string_view s, int& out) {
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// "<body>*hh": checks the checksum of body; `rest` gets what follows hh.
bool CheckChecksum(std::string_view s, std::string_view& body, std::string_view& rest, std::string& reason) {
  const size_t star = s.find('*');
  if (star == std::string_view::npos || star + 3 > s.size()) {
    reason = "missing checksum";
    return false;
  }
  const int hi = HexDigit(s[star + 1]), lo = HexDigit(s[star + 2]);
  if (hi < 0 || lo < 0) {
    reason = "malformed checksum";
    return false;
  }
  body = s.substr(0, star);
  rest = s.substr(star + 3);
  if (NmeaChecksum(body) != hi * 16 + lo) {
    reason = "checksum mismatch";
    return false;
  }
  return true;
}

bool AllDigits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// A UNIX time in seconds or milliseconds (13+ digits).
double UnixTime(std::string_view digits) {
  const double v = std::strtod(std::string(digits).c_str(), nullptr);
  return digits.size() >= 13 ? v / 1000.0 : v;
}

// The sentence formatter of "!AIVDM…"/"AIVDM…": characters 3–5 after the '!'.
bool HasFormatter(std::string_view sentence, std::string_view formatter) {
  return sentence.size() >= 6 && sentence.substr(3, 3) == formatter;
}

}  // namespace

int64_t SentenceStats::RejectedTotal() const {
  int64_t n = 0;
  for (const auto& [reason, count] : rejected) n += count;
  return n;
}

uint8_t NmeaChecksum(std::string_view s) {
  uint8_t x = 0;
  for (char c : s) x ^= static_cast<uint8_t>(c);
  return x;
}

bool ParseTagBlock(std::string_view block, TagBlock& out, std::string& reason) {
  std::string_view body, rest;
  if (!CheckChecksum(block, body, rest, reason)) {
    reason = "tag block: " + reason;
    return false;
  }
  for (std::string_view field : SplitFields(body)) {
    if (field.size() < 2 || field[1] != ':') {
      reason = "tag block: malformed field";
      return false;
    }
    const std::string_view value = field.substr(2);
    switch (field[0]) {
      case 'c':
        if (!AllDigits(value)) {
          reason = "tag block: bad time";
          return false;
        }
        out.time_s = UnixTime(value);
        break;
      case 's':
        out.source = std::string(value);
        break;
      case 'g': {
        const size_t a = value.find('-'), b = a == std::string_view::npos ? a : value.find('-', a + 1);
        if (b == std::string_view::npos || !ParseInt(value.substr(0, a), out.group_part) ||
            !ParseInt(value.substr(a + 1, b - a - 1), out.group_parts) ||
            !ParseInt(value.substr(b + 1), out.group_id)) {
          reason = "tag block: bad group";
          return false;
        }
        break;
      }
      default:
        break;  // d (destination), n (line count), r (relative time), t (text): not needed
    }
  }
  out.valid = true;
  return true;
}

bool AppendPayloadBits(std::string_view payload, int fill, std::vector<uint8_t>& bits) {
  const size_t start = bits.size();
  for (char c : payload) {
    int v = static_cast<unsigned char>(c) - 48;
    if (v > 40) v -= 8;
    if (v < 0 || v > 63 || (c > 'W' && c < '`') || c > 'w') return false;
    for (int b = 5; b >= 0; --b) bits.push_back(static_cast<uint8_t>((v >> b) & 1));
  }
  const size_t added = bits.size() - start;
  bits.resize(start + added - std::min<size_t>(added, static_cast<size_t>(fill)));
  return true;
}

std::optional<RawMessage> SentenceAssembler::Reject(const std::string& reason) {
  ++stats_.rejected[reason];
  last_reason_ = reason;
  return std::nullopt;
}

std::optional<RawMessage> SentenceAssembler::Feed(std::string_view line) {
  ++stats_.lines;
  last_reason_.clear();
  while (!line.empty() && (line.back() == ' ' || line.back() == '\r' || line.back() == '\n' || line.back() == '\t'))
    line.remove_suffix(1);
  if (line.empty() || line[0] == '#') {
    ++stats_.blank;
    return std::nullopt;
  }
  // Incomplete multipart messages time out by sentences seen since their first part.
  for (auto it = pending_.begin(); it != pending_.end();)
    if (stats_.lines - it->second.first_line > o_.multipart_timeout_lines) {
      ++stats_.rejected["multipart timeout (lost fragment)"];
      it = pending_.erase(it);
    } else {
      ++it;
    }

  TagBlock tag;
  if (line[0] == '\\') {
    const size_t end = line.find('\\', 1);
    if (end == std::string_view::npos) return Reject("tag block: unterminated");
    std::string reason;
    if (!ParseTagBlock(line.substr(1, end - 1), tag, reason)) return Reject(reason);
    line = line.substr(end + 1);
    if (line.empty()) return Reject("tag block without sentence");
  }
  if (line[0] == '$' || (line[0] == '!' && !HasFormatter(line, "VDM") && !HasFormatter(line, "VDO"))) {
    ++stats_.other;
    return std::nullopt;
  }
  if (line[0] != '!') return Reject("not an NMEA sentence (no '!' or '$')");
  ++stats_.sentences;

  std::string_view body, rest;
  std::string reason;
  if (!CheckChecksum(line.substr(1), body, rest, reason)) return Reject(reason);
  const auto f = SplitFields(body);
  if (f.size() != 7) return Reject("wrong number of fields");
  int parts = 0, part = 0, fill = 0, seq = -1;
  if (!ParseInt(f[1], parts) || parts < 1 || parts > 9) return Reject("bad fragment count");
  if (!ParseInt(f[2], part) || part < 1 || part > parts) return Reject("bad fragment number");
  if (!f[3].empty() && (!ParseInt(f[3], seq) || seq < 0 || seq > 9)) return Reject("bad sequence id");
  if (f[4].size() > 1) return Reject("bad channel");
  if (!ParseInt(f[6], fill) || fill < 0 || fill > 5) return Reject("bad fill bits");
  if (f[5].empty()) return Reject("empty payload");

  const char channel = f[4].empty() ? 0 : f[4][0];
  if (!tag.time_s) {
    const auto extra = SplitFields(rest);
    if (extra.size() > 1 && AllDigits(extra.back())) tag.time_s = UnixTime(extra.back());
  }
  const auto key = std::make_pair(channel, seq);
  auto fresh = [&] {
    RawMessage m;
    m.channel = channel;
    m.own = HasFormatter(line, "VDO");
    m.time_s = tag.time_s;
    m.source = tag.source;
    return m;
  };

  if (parts == 1) {
    RawMessage m = fresh();
    if (!AppendPayloadBits(f[5], fill, m.bits)) return Reject("invalid payload character");
    m.line = stats_.lines;
    ++stats_.messages;
    return m;
  }
  auto it = pending_.find(key);
  if (part == 1) {
    if (it != pending_.end()) ++stats_.rejected["multipart restarted (lost fragment)"];
    Pending p;
    p.parts = parts;
    p.next = 2;
    p.first_line = stats_.lines;
    p.message = fresh();
    if (fill != 0) return Reject("fill bits in a non-final fragment");
    if (!AppendPayloadBits(f[5], 0, p.message.bits)) {
      if (it != pending_.end()) pending_.erase(it);
      return Reject("invalid payload character");
    }
    pending_[key] = std::move(p);
    return std::nullopt;
  }
  if (it == pending_.end()) return Reject("fragment without its first part");
  Pending& p = it->second;
  if (p.parts != parts || p.next != part) {
    pending_.erase(it);
    return Reject("fragment out of order (lost fragment)");
  }
  if (part < parts && fill != 0) {
    pending_.erase(it);
    return Reject("fill bits in a non-final fragment");
  }
  if (!AppendPayloadBits(f[5], fill, p.message.bits)) {
    pending_.erase(it);
    return Reject("invalid payload character");
  }
  if (++p.next <= parts) return std::nullopt;
  RawMessage m = std::move(p.message);
  if (tag.time_s) m.time_s = tag.time_s;
  m.line = stats_.lines;
  pending_.erase(it);
  ++stats_.messages;
  return m;
}

void SentenceAssembler::Finish() {
  if (!pending_.empty())
    stats_.rejected["incomplete multipart at end of input"] += static_cast<int64_t>(pending_.size());
  pending_.clear();
}

}  // namespace specht::ais
