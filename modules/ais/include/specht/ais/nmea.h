// specht/ais/nmea.h: NMEA 0183 AIS sentences to message bit strings (ITU-R M.1371,
// IEC 61162-1). A line is
//   [\<tag block>*hh\]!AIVDM,<parts>,<part>,<seq id>,<channel>,<payload>,<fill>*hh[,<extra>...]
// (!AIVDO for the own vessel). The checksum hh is the XOR of the characters between
// '!' and '*'; the tag block (c: UNIX time, s: source, g: group, …) has its own.
// Payload characters carry 6 bits each ("armouring": c − 48, minus another 8 when
// above 40), the last character's `fill` low bits are padding.
//
// Multipart messages are reassembled by (channel, sequence id): parts must arrive in
// order; a new first part, a part out of order, or a message not completed within
// `multipart_timeout_lines` sentences drops what was collected (counted by reason).
// Other NMEA sentences (GPS, …) may be interleaved and are counted as "other".
// Trailing fields after the checksum (receiver metadata, a UNIX time as the last
// field) are allowed; a final all-digit field is taken as the receive time when there
// is no tag block time.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "specht/core/params.h"

namespace specht::ais {

struct TagBlock {
  std::optional<double> time_s;                       // c: UNIX time (seconds or milliseconds)
  std::string source;                                 // s: receiver / station
  int group_part = 0, group_parts = 0, group_id = 0;  // g: part-parts-id
  bool valid = false;
};

// One complete AIS message as bits (one bit per byte, most significant first).
struct RawMessage {
  std::vector<uint8_t> bits;
  char channel = 0;  // 'A', 'B', '1', '2' or 0
  bool own = false;  // !AIVDO
  std::optional<double> time_s;
  std::string source;
  int64_t line = 0;  // line of the last part
};

// Section "ais_decoder".
struct SentenceOptions {
  int multipart_timeout_lines = 100;
  template <class V>
  void Visit(V& v) {
    v.Param("multipart_timeout_lines", multipart_timeout_lines,
            "sentences after which an incomplete multipart message is dropped", params::Range::Of(1, 1000000));
  }
};

struct SentenceStats {
  int64_t lines = 0, sentences = 0, messages = 0, other = 0, blank = 0;
  std::map<std::string, int64_t> rejected;  // reason → count
  int64_t RejectedTotal() const;
};

class SentenceAssembler {
 public:
  explicit SentenceAssembler(SentenceOptions o = {}) : o_(o) {}

  // Feeds one line (without end-of-line); returns a message when the line completes
  // one. Never throws on bad input: the line is counted in stats().rejected under
  // its reason, and `last_reason()` names it.
  std::optional<RawMessage> Feed(std::string_view line);
  // Drops incomplete multipart messages still waiting (end of input).
  void Finish();

  const SentenceStats& stats() const { return stats_; }
  const std::string& last_reason() const { return last_reason_; }

 private:
  struct Pending {
    int parts = 0, next = 0;
    int64_t first_line = 0;
    RawMessage message;
  };
  std::optional<RawMessage> Reject(const std::string& reason);
  SentenceOptions o_;
  SentenceStats stats_;
  std::string last_reason_;
  std::map<std::pair<char, int>, Pending> pending_;
};

// Building blocks (exposed for tests).
// XOR of the characters of `s`.
uint8_t NmeaChecksum(std::string_view s);
// Parses a tag block's content (between the backslashes); false with `reason`.
bool ParseTagBlock(std::string_view block, TagBlock& out, std::string& reason);
// De-armours a payload, appending its bits minus `fill` to `bits`; false on a
// character outside the 6-bit alphabet.
bool AppendPayloadBits(std::string_view payload, int fill, std::vector<uint8_t>& bits);

}  // namespace specht::ais
