// specht/ais/decoder.h: the decoding chain for a stream of NMEA lines —
// sentences (nmea.h) → messages (messages.h) → class B static parts joined — with
// counts per message type and per rejection reason. Bad input is never fatal: each
// rejected line or message is counted under its reason.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "specht/ais/messages.h"
#include "specht/ais/nmea.h"

namespace specht::ais {

struct DecoderStats {
  SentenceStats sentences;
  std::map<std::string, int64_t> rejected_messages;  // reason → count
  std::map<int, int64_t> per_type;                   // decoded messages by type
  int64_t header_only = 0;                           // types decoded to their header
  int64_t emitted = 0;
  int64_t RejectedTotal() const;
  nlohmann::json ToJson() const;
};

class Decoder {
 public:
  using Sink = std::function<void(const Message&)>;
  Decoder(const SentenceOptions& o, Sink sink) : sentences_(o), sink_(std::move(sink)) {}
  void Feed(std::string_view line);
  void Finish();  // end of input: incomplete multipart messages are counted
  DecoderStats stats() const;

 private:
  SentenceAssembler sentences_;
  StaticDataJoiner joiner_;
  DecoderStats stats_;
  Sink sink_;
};

// Decodes a file (gzip or plain), calling `sink` per message. InputError when the
// file cannot be opened.
DecoderStats DecodeFile(const std::string& path, const SentenceOptions& o, const Decoder::Sink& sink);

}  // namespace specht::ais
