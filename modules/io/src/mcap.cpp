#include "specht/io/mcap.h"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "specht/core/error.h"
#include "specht/io/dataset.h"

namespace specht::io {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
enum Op : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// Little-endian fields, MCAP's only byte order.
template <class T>
void Le(std::string& out, T v) {
  for (size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<char>((static_cast<uint64_t>(v) >> (8 * i)) & 0xff));
}
void PutString(std::string& out, const std::string& s) {
  Le<uint32_t>(out, static_cast<uint32_t>(s.size()));
  out += s;
}
std::string Record(uint8_t op, const std::string& body) {
  std::string r;
  Le<uint8_t>(r, op);
  Le<uint64_t>(r, body.size());
  return r + body;
}
uint32_t Crc(uint32_t crc, const std::string& bytes) {
  return static_cast<uint32_t>(
      crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size())));
}

// Reads fields from a record body; a field past its end is a malformed record.
class RecordFields {
 public:
  explicit RecordFields(const std::string& body) : body_(body) {}
  template <class T>
  T Get() {
    Need(sizeof(T));
    uint64_t v = 0;
    for (size_t i = 0; i < sizeof(T); ++i) v |= static_cast<uint64_t>(static_cast<uint8_t>(body_[at_ + i])) << (8 * i);
    at_ += sizeof(T);
    return static_cast<T>(v);
  }
  std::string String() { return Bytes(Get<uint32_t>()); }
  std::string Bytes(uint64_t n) {
    Need(n);
    std::string s = body_.substr(at_, n);
    at_ += n;
    return s;
  }
  std::string Rest() { return Bytes(body_.size() - at_); }

 private:
  void Need(uint64_t n) const {
    if (n > body_.size() - at_) throw InputError("a field runs past its record's end");
  }
  const std::string& body_;
  size_t at_ = 0;
};

}  // namespace

McapWriter::McapWriter(std::string path, size_t chunk_bytes) : path_(std::move(path)), chunk_bytes_(chunk_bytes) {
  const fs::path p(path_);
  tmp_path_ = (p.parent_path() / (p.stem().string() + ".tmp.mcap")).string();
  out_.open(tmp_path_, std::ios::binary | std::ios::trunc);
  if (!out_) throw RuntimeError(tmp_path_ + ": cannot write");
  Put(std::string(kMagic, 8));
  std::string header;
  PutString(header, "ros2");
  PutString(header, "specht");
  Put(Record(kHeader, header));
}

McapWriter::~McapWriter() {
  try {
    Close();
  } catch (...) {  // a destructor must not throw; Close() reports when called
  }
}

void McapWriter::Put(const std::string& bytes) {
  out_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  data_crc_ = Crc(data_crc_, bytes);
  offset_ += bytes.size();
}

uint16_t McapWriter::AddSchema(const std::string& name, const std::string& encoding, const std::string& data) {
  const uint16_t id = ++schema_count_;  // 0 means "no schema"
  std::string body;
  Le<uint16_t>(body, id);
  PutString(body, name);
  PutString(body, encoding);
  PutString(body, data);
  const std::string r = Record(kSchema, body);
  Put(r);
  schemas_ += r;
  return id;
}

uint16_t McapWriter::AddChannel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding) {
  const uint16_t id = channel_count_++;
  std::string body;
  Le<uint16_t>(body, id);
  Le<uint16_t>(body, schema_id);
  PutString(body, topic);
  PutString(body, message_encoding);
  Le<uint32_t>(body, 0);  // metadata: an empty map
  const std::string r = Record(kChannel, body);
  Put(r);
  channels_ += r;
  return id;
}

void McapWriter::Write(uint16_t channel_id, uint64_t log_time_ns, const std::vector<uint8_t>& data) {
  std::string body;
  Le<uint16_t>(body, channel_id);
  Le<uint32_t>(body, sequence_[channel_id]++);
  Le<uint64_t>(body, log_time_ns);
  Le<uint64_t>(body, log_time_ns);  // publish time: the same instant here
  body.append(reinterpret_cast<const char*>(data.data()), data.size());
  chunk_index_[channel_id].emplace_back(log_time_ns, chunk_.size());
  chunk_ += Record(kMessage, body);
  chunk_start_ns_ = std::min(chunk_start_ns_, log_time_ns), chunk_end_ns_ = std::max(chunk_end_ns_, log_time_ns);
  start_ns_ = std::min(start_ns_, log_time_ns), end_ns_ = std::max(end_ns_, log_time_ns);
  ++message_count_, ++channel_counts_[channel_id];
  if (chunk_.size() >= chunk_bytes_) FlushChunk();
}

void McapWriter::FlushChunk() {
  if (chunk_.empty()) return;
  std::string compressed(ZSTD_compressBound(chunk_.size()), '\0');
  const size_t n = ZSTD_compress(compressed.data(), compressed.size(), chunk_.data(), chunk_.size(), 3);
  if (ZSTD_isError(n)) throw RuntimeError(path_ + ": zstd: " + ZSTD_getErrorName(n));
  compressed.resize(n);
  std::string body;
  Le<uint64_t>(body, chunk_start_ns_);
  Le<uint64_t>(body, chunk_end_ns_);
  Le<uint64_t>(body, chunk_.size());
  Le<uint32_t>(body, Crc(0, chunk_));
  PutString(body, "zstd");
  Le<uint64_t>(body, compressed.size());
  body += compressed;
  const uint64_t chunk_start = offset_;
  const std::string chunk = Record(kChunk, body);
  Put(chunk);
  // Message Index records, one per channel, and where each lies, for the Chunk Index.
  std::string offsets;
  const uint64_t index_start = offset_;
  for (const auto& [channel, entries] : chunk_index_) {
    std::string mi;
    Le<uint16_t>(mi, channel);
    Le<uint32_t>(mi, static_cast<uint32_t>(entries.size() * 16));
    for (const auto& [t, at] : entries) Le<uint64_t>(mi, t), Le<uint64_t>(mi, at);
    Le<uint16_t>(offsets, channel);
    Le<uint64_t>(offsets, offset_);
    Put(Record(kMessageIndex, mi));
  }
  std::string ci;
  Le<uint64_t>(ci, chunk_start_ns_);
  Le<uint64_t>(ci, chunk_end_ns_);
  Le<uint64_t>(ci, chunk_start);
  Le<uint64_t>(ci, chunk.size());
  Le<uint32_t>(ci, static_cast<uint32_t>(offsets.size()));
  ci += offsets;
  Le<uint64_t>(ci, offset_ - index_start);
  PutString(ci, "zstd");
  Le<uint64_t>(ci, compressed.size());
  Le<uint64_t>(ci, chunk_.size());
  chunk_indexes_ += Record(kChunkIndex, ci);
  ++chunk_count_;
  chunk_.clear();
  chunk_index_.clear();
  chunk_start_ns_ = UINT64_MAX, chunk_end_ns_ = 0;
}

void McapWriter::Close() {
  if (closed_) return;
  closed_ = true;
  FlushChunk();
  std::string data_end;
  Le<uint32_t>(data_end, data_crc_);
  Put(Record(kDataEnd, data_end));

  std::string stats;
  Le<uint64_t>(stats, message_count_);
  Le<uint16_t>(stats, schema_count_);
  Le<uint32_t>(stats, channel_count_);
  Le<uint32_t>(stats, 0);  // attachments
  Le<uint32_t>(stats, 0);  // metadata
  Le<uint32_t>(stats, chunk_count_);
  Le<uint64_t>(stats, message_count_ ? start_ns_ : 0);
  Le<uint64_t>(stats, end_ns_);
  Le<uint32_t>(stats, static_cast<uint32_t>(channel_counts_.size() * 10));
  for (const auto& [channel, count] : channel_counts_) Le<uint16_t>(stats, channel), Le<uint64_t>(stats, count);

  // The summary: each group and where it starts; then the offsets of the groups.
  const uint64_t summary_start = offset_;
  std::string summary, summary_offsets;
  const auto group = [&](uint8_t op, const std::string& records) {
    if (records.empty()) return;
    Le<uint8_t>(summary_offsets, op);
    Le<uint64_t>(summary_offsets, summary_start + summary.size());
    Le<uint64_t>(summary_offsets, records.size());
    summary += records;
  };
  group(kSchema, schemas_);
  group(kChannel, channels_);
  group(kStatistics, Record(kStatistics, stats));
  group(kChunkIndex, chunk_indexes_);
  std::string offsets_section;
  for (size_t i = 0; i < summary_offsets.size(); i += 17)
    offsets_section += Record(kSummaryOffset, summary_offsets.substr(i, 17));
  const uint64_t summary_offset_start = summary_start + summary.size();
  std::string footer;
  Le<uint8_t>(footer, kFooter);
  Le<uint64_t>(footer, 20);
  Le<uint64_t>(footer, summary_start);
  Le<uint64_t>(footer, summary_offset_start);
  // CRC of the summary through the footer's summary_offset_start field.
  Le<uint32_t>(footer, Crc(0, summary + offsets_section + footer));
  Put(summary + offsets_section + footer + std::string(kMagic, 8));
  out_.close();
  if (!out_) throw RuntimeError(tmp_path_ + ": write failed");
  fs::rename(tmp_path_, path_);
}

McapReader::McapReader(std::string path) : path_(std::move(path)), in_(path_, std::ios::binary) {
  if (!in_) throw InputError(path_ + ": cannot open");
  in_.seekg(0, std::ios::end);
  size_ = static_cast<uint64_t>(in_.tellg());
  in_.seekg(0);
  char magic[8] = {};
  in_.read(magic, 8);
  if (!in_ || std::memcmp(magic, kMagic, 8) != 0) throw InputError(path_ + ": not an MCAP file (no magic)");
  offset_ = 8;
}

double McapReader::FractionRead() const { return size_ > 0 ? static_cast<double>(offset_) / size_ : 1.0; }

bool McapReader::NextRecord(uint8_t& opcode, std::string& body, uint64_t& at) {
  at = offset_;
  if (size_ - offset_ < 9)
    throw DatasetError(
        path_, messages_, static_cast<int64_t>(at),
        "the file ends before its data section does (truncated; " + std::to_string(messages_) + " messages read)");
  char head[9];
  in_.read(head, 9);
  opcode = static_cast<uint8_t>(head[0]);
  uint64_t length = 0;
  for (int i = 0; i < 8; ++i) length |= static_cast<uint64_t>(static_cast<uint8_t>(head[1 + i])) << (8 * i);
  if (length > size_ - offset_ - 9)
    throw DatasetError(path_, messages_, static_cast<int64_t>(at),
                       "record 0x" + std::to_string(opcode) + " of " + std::to_string(length) +
                           " bytes runs past the file's end (truncated; " + std::to_string(messages_) +
                           " messages read)");
  body.resize(length);
  in_.read(body.data(), static_cast<std::streamsize>(length));
  offset_ += 9 + length;
  return true;
}

void McapReader::Take(uint8_t opcode, const std::string& body, uint64_t at) {
  try {
    RecordFields f(body);
    switch (opcode) {
      case kHeader:
        profile_ = f.String();
        break;
      case kSchema: {
        const auto id = f.Get<uint16_t>();
        schema_names_[id] = f.String();
        break;
      }
      case kChannel: {
        const auto id = f.Get<uint16_t>();
        Channel c;
        c.schema_id = f.Get<uint16_t>();
        c.topic = f.String();
        c.encoding = f.String();
        channels_[id] = c;
        break;
      }
      case kMessage: {
        const auto id = f.Get<uint16_t>();
        f.Get<uint32_t>();
        McapMessage m;
        m.log_time_ns = f.Get<uint64_t>();
        f.Get<uint64_t>();
        const std::string data = f.Rest();
        const auto c = channels_.find(id);
        if (c == channels_.end()) throw InputError("a message on unknown channel " + std::to_string(id));
        m.topic = c->second.topic, m.message_encoding = c->second.encoding;
        m.schema_name = schema_names_.count(c->second.schema_id) ? schema_names_[c->second.schema_id] : "";
        m.data.assign(data.begin(), data.end());
        m.index = messages_++;
        pending_.push_back(std::move(m));
        break;
      }
      case kChunk: {
        f.Get<uint64_t>(), f.Get<uint64_t>();
        const auto uncompressed_size = f.Get<uint64_t>();
        const auto crc = f.Get<uint32_t>();
        const std::string compression = f.String();
        const std::string records = f.Bytes(f.Get<uint64_t>());
        // A chunk's claim of its size sizes a buffer: bounded by what compression can do.
        if (!compression.empty() && uncompressed_size > std::max<uint64_t>(64 << 20, 2048 * records.size()))
          throw InputError("a chunk of " + std::to_string(records.size()) + " bytes claiming " +
                           std::to_string(uncompressed_size) + " uncompressed");
        std::string plain;
        if (compression.empty()) {
          plain = records;
        } else if (compression == "zstd") {
          plain.resize(uncompressed_size);
          const size_t n = ZSTD_decompress(plain.data(), plain.size(), records.data(), records.size());
          if (ZSTD_isError(n) || n != uncompressed_size) throw InputError("a zstd chunk that does not decompress");
        } else if (compression == "lz4") {
          plain.resize(uncompressed_size);
          LZ4F_dctx* ctx = nullptr;
          LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION);
          size_t out_n = plain.size(), in_n = records.size();
          const size_t rc = LZ4F_decompress(ctx, plain.data(), &out_n, records.data(), &in_n, nullptr);
          LZ4F_freeDecompressionContext(ctx);
          if (LZ4F_isError(rc) || out_n != uncompressed_size) throw InputError("an lz4 chunk that does not decompress");
        } else {
          throw InputError("a chunk compressed with '" + compression + "', which is not read (zstd, lz4, none)");
        }
        if (crc != 0 && Crc(0, plain) != crc) throw InputError("a chunk whose CRC does not match its records");
        for (size_t i = 0; i < plain.size();) {  // the chunk's own records
          if (plain.size() - i < 9) throw InputError("a chunk whose last record is cut");
          const std::string head_bytes = plain.substr(i, 9);
          RecordFields head(head_bytes);
          const auto op = head.Get<uint8_t>();
          const auto n = head.Get<uint64_t>();
          if (n > plain.size() - i - 9) throw InputError("a chunk record runs past the chunk's end");
          Take(op, plain.substr(i + 9, n), at);
          i += 9 + n;
        }
        break;
      }
      case kDataEnd:
      case kFooter:
        data_end_ = true;
        break;
      default:  // message indexes, attachments, metadata, summary records: not needed to replay
        break;
    }
  } catch (const DatasetError&) {
    throw;
  } catch (const InputError& e) {
    throw DatasetError(path_, messages_, static_cast<int64_t>(at), e.what());
  }
}

std::optional<McapMessage> McapReader::Next() {
  while (next_pending_ >= pending_.size()) {
    pending_.clear(), next_pending_ = 0;
    if (data_end_) return std::nullopt;
    uint8_t op = 0;
    std::string body;
    uint64_t at = 0;
    NextRecord(op, body, at);
    Take(op, body, at);
  }
  return std::move(pending_[next_pending_++]);
}

}  // namespace specht::io
