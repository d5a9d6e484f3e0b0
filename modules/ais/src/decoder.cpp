#include "specht/ais/decoder.h"

#include "specht/io/line_reader.h"

namespace specht::ais {

int64_t DecoderStats::RejectedTotal() const {
  int64_t n = sentences.RejectedTotal();
  for (const auto& [reason, count] : rejected_messages) n += count;
  return n;
}

nlohmann::json DecoderStats::ToJson() const {
  nlohmann::json types = nlohmann::json::object();
  for (const auto& [t, n] : per_type) types[std::to_string(t)] = n;
  return {{"lines", sentences.lines},
          {"sentences", sentences.sentences},
          {"other_sentences", sentences.other},
          {"messages", sentences.messages},
          {"emitted", emitted},
          {"header_only", header_only},
          {"per_type", types},
          {"rejected_sentences", sentences.rejected},
          {"rejected_messages", rejected_messages},
          {"rejected_total", RejectedTotal()}};
}

void Decoder::Feed(std::string_view line) {
  const auto raw = sentences_.Feed(line);
  if (!raw) return;
  Message m;
  std::string reason;
  if (!DecodeMessage(*raw, m, reason)) {
    ++stats_.rejected_messages[reason];
    return;
  }
  ++stats_.per_type[m.type];
  if (!m.complete) ++stats_.header_only;
  if (auto out = joiner_.Feed(m)) {
    ++stats_.emitted;
    sink_(*out);
  }
}

void Decoder::Finish() { sentences_.Finish(); }

DecoderStats Decoder::stats() const {
  DecoderStats s = stats_;
  s.sentences = sentences_.stats();
  if (joiner_.lone_part_b() > 0) s.rejected_messages["type 24 part B without its part A"] = joiner_.lone_part_b();
  return s;
}

DecoderStats DecodeFile(const std::string& path, const SentenceOptions& o, const Decoder::Sink& sink) {
  io::LineReader lines(path);
  Decoder decoder(o, sink);
  std::string line;
  while (lines.Next(line)) decoder.Feed(line);
  decoder.Finish();
  return decoder.stats();
}

}  // namespace specht::ais
