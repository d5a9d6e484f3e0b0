// specht/io/mcap.h: MCAP files (https://mcap.dev/spec, version 0), the log format
// Foxglove opens and ROS 2 records since Iron.
//
// McapWriter writes the layout the spec recommends for seekable readers:
//   magic, Header (profile "ros2"), Schema and Channel records as they are added,
//   Chunks (messages, zstd-compressed, ≤ chunk_bytes uncompressed) each followed by
//   its Message Index records, Data End (with the data section's CRC-32);
//   the summary: Schemas, Channels, Statistics, Chunk Indexes, then Summary Offsets;
//   Footer, magic.
// The file is written under a temporary name and renamed by Close(), so an
// interrupted run never leaves a file without its summary under the final name.
//
// McapReader reads the data section linearly (chunks decompressed: zstd, lz4 or
// none), which serves a file whose summary is missing: a truncated file yields the
// messages before the cut, then throws DatasetError naming the byte offset.
#pragma once

#include <cstdint>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace specht::io {

class McapWriter {
 public:
  // `path` is created (its directory must exist); nothing is written until Close()
  // renames it into place.
  explicit McapWriter(std::string path, size_t chunk_bytes = 1 << 20);
  ~McapWriter();  // closes
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // A schema (`encoding` e.g. "ros2msg", `data` its definition); returns its id.
  uint16_t AddSchema(const std::string& name, const std::string& encoding, const std::string& data);
  // A channel on `topic` carrying `message_encoding` ("cdr") messages; returns its id.
  uint16_t AddChannel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding);
  // One message; log_time and publish_time in nanoseconds.
  void Write(uint16_t channel_id, uint64_t log_time_ns, const std::vector<uint8_t>& data);
  // Finishes the file (summary, footer) and renames it into place. Idempotent.
  void Close();

  uint64_t messages() const { return message_count_; }
  const std::map<uint16_t, uint64_t>& channel_messages() const { return channel_counts_; }

 private:
  struct Chunk;
  void FlushChunk();
  void Put(const std::string& bytes);  // to the file, counting the data section's CRC

  std::string path_, tmp_path_;
  std::ofstream out_;
  size_t chunk_bytes_;
  bool closed_ = false;
  uint64_t offset_ = 0;
  uint32_t data_crc_ = 0;
  std::string schemas_, channels_, chunk_indexes_;  // summary records, as written
  std::map<uint16_t, uint32_t> sequence_;
  std::map<uint16_t, uint64_t> channel_counts_;
  uint64_t message_count_ = 0, start_ns_ = UINT64_MAX, end_ns_ = 0;
  uint32_t chunk_count_ = 0;
  uint16_t schema_count_ = 0, channel_count_ = 0;
  // The open chunk: its records and, per channel, (log time, offset) of each message.
  std::string chunk_;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;
  uint64_t chunk_start_ns_ = UINT64_MAX, chunk_end_ns_ = 0;
};

struct McapMessage {
  std::string topic, schema_name, message_encoding;
  uint64_t log_time_ns = 0;
  std::vector<uint8_t> data;
  int64_t index = 0;  // 0-based, in file order
};

class McapReader {
 public:
  // Throws InputError when the file is missing or does not start with MCAP's magic.
  explicit McapReader(std::string path);
  // The next message, or nullopt at the data section's end. Throws DatasetError at a
  // truncated or malformed record (naming its byte offset) or an unknown compression.
  std::optional<McapMessage> Next();
  double FractionRead() const;
  const std::string& profile() const { return profile_; }

 private:
  bool NextRecord(uint8_t& opcode, std::string& body, uint64_t& at);  // from the file
  void Take(uint8_t opcode, const std::string& body, uint64_t at);    // schemas, channels, chunks
  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0, offset_ = 0;
  bool data_end_ = false;
  std::string profile_;
  struct Channel {
    std::string topic, encoding;
    uint16_t schema_id = 0;
  };
  std::map<uint16_t, std::string> schema_names_;
  std::map<uint16_t, Channel> channels_;
  std::vector<McapMessage> pending_;  // a decompressed chunk's messages
  size_t next_pending_ = 0;
  int64_t messages_ = 0;
};

}  // namespace specht::io
