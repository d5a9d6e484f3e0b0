// The AIS decoder against gpsd's expected output, hand-made sentences for the
// sentence layer (tag blocks, multipart, checksums), and random corruption.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>

#include "specht/ais/decoder.h"
#include "test_support.h"

namespace specht::ais {
namespace {

using specht::testing::DataDir;

std::string NmeaDir() {
  const std::string d = DataDir();
  return d.empty() ? "" : d + "/ais/nmea";
}

std::vector<Message> DecodeAll(const std::string& path, DecoderStats* stats = nullptr) {
  std::vector<Message> out;
  const DecoderStats s = DecodeFile(path, {}, [&](const Message& m) { out.push_back(m); });
  if (stats != nullptr) *stats = s;
  return out;
}

// gpsd prints "not available" as the scaled sentinel; we give null.
nlohmann::json GpsdNotAvailable(int type, const std::string& field) {
  static const std::map<std::string, nlohmann::json> common = {{"lon", 181.0}, {"lat", 91.0},     {"heading", 511},
                                                               {"second", 60}, {"course", 360.0}, {"speed", 102.3}};
  if (type == 27 && field == "speed") return 63;
  if (type == 27 && field == "course") return 511;
  if (type == 9 && field == "speed") return 1023;
  if (type == 9 && field == "alt") return 4095;
  const auto it = common.find(field);
  return it == common.end() ? nlohmann::json() : it->second;
}

// Every field gpsd reports, except its presentation-only ones, must be ours with the
// same value (numbers to gpsd's printed precision).
void ExpectSameFields(const nlohmann::json& gpsd, const Message& m, int index) {
  const nlohmann::json ours = m.ToJson();
  for (const auto& [key, expected] : gpsd.items()) {
    if (key == "class" || key == "device" || key == "scaled" ||
        (key.size() > 5 && key.substr(key.size() - 5) == "_text"))
      continue;
    SCOPED_TRACE("message " + std::to_string(index) + " type " + std::to_string(m.type) + " field " + key);
    if (key == "turn") {
      const auto rot = m.Number("rot");
      EXPECT_EQ(TurnText(rot ? static_cast<int>(*rot) : -128), expected.get<std::string>());
      continue;
    }
    ASSERT_TRUE(ours.contains(key)) << gpsd.dump();
    nlohmann::json got = ours[key];
    if (got.is_null()) got = GpsdNotAvailable(m.type, key);
    if (expected.is_number()) {
      ASSERT_TRUE(got.is_number()) << got.dump();
      EXPECT_NEAR(got.get<double>(), expected.get<double>(), 6e-5) << gpsd.dump();
    } else {
      EXPECT_EQ(got, expected) << gpsd.dump();
    }
  }
}

const std::set<int> kSupported = {1, 2, 3, 4, 5, 9, 11, 18, 19, 24, 27};

TEST(AisDecoderTest, GpsdSampleDecodesToGpsdsFieldsAndValues) {
  if (NmeaDir().empty()) SPECHT_SKIP() << "no data dir";
  const auto messages = DecodeAll(NmeaDir() + "/gpsd-sample.aivdm");
  std::vector<nlohmann::json> expected;
  std::ifstream chk(NmeaDir() + "/gpsd-sample.aivdm.js.chk");
  std::string line;
  while (std::getline(chk, line))
    if (!line.empty()) expected.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(expected.size(), 97u);
  // The same messages in the same order (type and MMSI), then field by field for
  // every type we decode in full.
  ASSERT_EQ(messages.size(), expected.size());
  int compared = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(messages[i].type, expected[i]["type"].get<int>()) << i;
    ASSERT_EQ(messages[i].mmsi, expected[i]["mmsi"].get<int64_t>()) << i;
    EXPECT_EQ(messages[i].repeat, expected[i]["repeat"].get<int>()) << i;
    if (!kSupported.count(messages[i].type)) continue;
    EXPECT_TRUE(messages[i].complete);
    ExpectSameFields(expected[i], messages[i], static_cast<int>(i));
    ++compared;
  }
  EXPECT_EQ(compared, 24);
}

TEST(AisDecoderTest, OtherLogsDecodeAndEveryRejectionHasAReason) {
  if (NmeaDir().empty()) SPECHT_SKIP() << "no data dir";
  for (const char* name :
       {"gpsd-ais-nmea.log", "libais-test.aivdm", "pyais-nmea-sample.txt", "signalk-nais400-merrimac.log"}) {
    SCOPED_TRACE(name);
    DecoderStats s;
    const auto messages = DecodeAll(NmeaDir() + "/" + name, &s);
    EXPECT_GT(messages.size(), 50u);
    for (const auto& [reason, n] : s.sentences.rejected) EXPECT_FALSE(reason.empty());
    for (const auto& [reason, n] : s.rejected_messages) EXPECT_FALSE(reason.empty());
    // Every line is accounted for: blank/comment, other NMEA, rejected, or an AIS
    // sentence that went into a message.
    EXPECT_LE(s.sentences.messages, s.sentences.sentences);
    EXPECT_EQ(s.emitted, static_cast<int64_t>(messages.size()));
  }
}

TEST(AisDecoderTest, SignalkLogHasOtherTalkersAndMultipartType5) {
  if (NmeaDir().empty()) SPECHT_SKIP() << "no data dir";
  DecoderStats s;
  const auto messages = DecodeAll(NmeaDir() + "/signalk-nais400-merrimac.log", &s);
  EXPECT_GT(s.sentences.other, 50);  // $GPGLL, $GPRMC, … interleaved
  EXPECT_GT(s.per_type[5], 0);
  for (const auto& m : messages)
    if (m.type == 5) {
      EXPECT_FALSE(m.Text("shipname").empty());
      EXPECT_TRUE(m.Number("shiptype").has_value());
    }
}

// A type 1 payload from the gpsd sample, re-wrapped in hand-made sentences.
const char* kType1 = "15RTgt0PAso;90TKcjM8h6g208CQ";
const char* kType5a = "55?MbV02;H;s<HtKR20EHE:0@T4@Dn2222222216L961O5Gf0NSQEp6ClRp8";
const char* kType5b = "88888888880";

std::string Sentence(const std::string& body) {
  char cs[8];
  std::snprintf(cs, sizeof(cs), "*%02X", NmeaChecksum(body));
  return "!" + body + cs;
}

std::string WithTag(const std::string& tag, const std::string& sentence) {
  char cs[8];
  std::snprintf(cs, sizeof(cs), "*%02X", NmeaChecksum(tag));
  return "\\" + tag + cs + "\\" + sentence;
}

std::vector<Message> DecodeLines(const std::vector<std::string>& lines, DecoderStats* stats = nullptr,
                                 SentenceOptions o = {}) {
  std::vector<Message> out;
  Decoder d(o, [&](const Message& m) { out.push_back(m); });
  for (const auto& l : lines) d.Feed(l);
  d.Finish();
  if (stats != nullptr) *stats = d.stats();
  return out;
}

TEST(AisSentenceTest, TagBlockGivesTimeAndSource) {
  const auto m =
      DecodeLines({WithTag("s:rORBCOMM000,c:1426032000", Sentence(std::string("AIVDM,1,1,,A,") + kType1 + ",0"))});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].mmsi, 371798000);
  ASSERT_TRUE(m[0].time_s.has_value());
  EXPECT_DOUBLE_EQ(*m[0].time_s, 1426032000.0);
  EXPECT_EQ(m[0].source, "rORBCOMM000");
  // Milliseconds are recognised by their length.
  const auto ms = DecodeLines({WithTag("c:1426032000500", Sentence(std::string("AIVDM,1,1,,A,") + kType1 + ",0"))});
  EXPECT_DOUBLE_EQ(*ms.at(0).time_s, 1426032000.5);
}

TEST(AisSentenceTest, BadTagBlockChecksumIsRejectedWithReason) {
  DecoderStats s;
  std::string line = WithTag("c:1426032000", Sentence(std::string("AIVDM,1,1,,A,") + kType1 + ",0"));
  line[3] = '5';  // the time changes, the tag checksum does not
  EXPECT_TRUE(DecodeLines({line}, &s).empty());
  EXPECT_EQ(s.sentences.rejected.count("tag block: checksum mismatch"), 1u);
}

TEST(AisSentenceTest, TrailingReceiveTimeIsUsedWithoutTagBlock) {
  const auto m = DecodeLines({Sentence(std::string("AIVDM,1,1,,A,") + kType1 + ",0") + ",s28089,d-103,1242958962"});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_DOUBLE_EQ(*m[0].time_s, 1242958962.0);
}

TEST(AisSentenceTest, MultipartReassemblesAcrossInterleavedSentences) {
  const std::string a = Sentence(std::string("AIVDM,2,1,3,A,") + kType5a + ",0");
  const std::string b = Sentence(std::string("AIVDM,2,2,3,A,") + kType5b + ",2");
  DecoderStats s;
  const auto m = DecodeLines({a, "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47",
                              Sentence(std::string("AIVDM,1,1,,B,") + kType1 + ",0"), b},
                             &s);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].type, 1);
  EXPECT_EQ(m[1].type, 5);
  EXPECT_EQ(m[1].Text("shipname"), "EVER DIADEM");
  EXPECT_EQ(m[1].Text("destination"), "NEW YORK");
  EXPECT_EQ(s.sentences.other, 1);
  EXPECT_EQ(s.RejectedTotal(), 0);
}

TEST(AisSentenceTest, LostFragmentsAreCountedNotFatal) {
  const std::string a = Sentence(std::string("AIVDM,2,1,3,A,") + kType5a + ",0");
  const std::string b = Sentence(std::string("AIVDM,2,2,3,A,") + kType5b + ",2");
  DecoderStats s;
  // part 2 alone; part 1 twice (the first loses its part 2); then a complete one.
  const auto m = DecodeLines({b, a, a, b}, &s);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(s.sentences.rejected.at("fragment without its first part"), 1);
  EXPECT_EQ(s.sentences.rejected.at("multipart restarted (lost fragment)"), 1);
  // A first part never completed times out.
  SentenceOptions o;
  o.multipart_timeout_lines = 3;
  std::vector<std::string> lines = {a};
  for (int i = 0; i < 5; ++i) lines.push_back(Sentence(std::string("AIVDM,1,1,,B,") + kType1 + ",0"));
  lines.push_back(b);
  DecodeLines(lines, &s, o);
  EXPECT_EQ(s.sentences.rejected.at("multipart timeout (lost fragment)"), 1);
  EXPECT_EQ(s.sentences.rejected.at("fragment without its first part"), 1);
}

TEST(AisSentenceTest, CorruptSentencesAreRejectedByReason) {
  const std::string good = Sentence(std::string("AIVDM,1,1,,A,") + kType1 + ",0");
  std::string flipped = good;
  flipped[20] = flipped[20] == 'A' ? 'B' : 'A';
  DecoderStats s;
  const auto m = DecodeLines({flipped, good.substr(0, good.size() - 2), Sentence("AIVDM,1,1,,A,15RT{gt0,0"),
                              Sentence(std::string("AIVDM,1,1,,A,") + kType1 + ",7"), Sentence("AIVDM,1,1,,A,15RT,0"),
                              Sentence("AIVDM,1,1,,A,0000000000,0"), "garbage"},
                             &s);
  EXPECT_TRUE(m.empty());
  EXPECT_EQ(s.sentences.rejected.at("checksum mismatch"), 1);
  EXPECT_EQ(s.sentences.rejected.at("missing checksum"), 1);
  EXPECT_EQ(s.sentences.rejected.at("invalid payload character"), 1);
  EXPECT_EQ(s.sentences.rejected.at("bad fill bits"), 1);
  EXPECT_EQ(s.rejected_messages.at("message shorter than its header (38 bits)"), 1);
  EXPECT_EQ(s.rejected_messages.at("unknown message type 0"), 1);
  EXPECT_EQ(s.sentences.rejected.at("not an NMEA sentence (no '!' or '$')"), 1);
}

TEST(AisMessageTest, NotAvailableValuesAreNull) {
  // gpsd sample: type 4 with every date field and the position "not available".
  const auto m = DecodeLines({"!AIVDM,1,1,,A,402Fha0000Htt<tSF0l4Q@000d20,0*65"});
  ASSERT_EQ(m.size(), 1u);
  EXPECT_FALSE(m[0].Number("lon").has_value());
  EXPECT_FALSE(m[0].Number("lat").has_value());
  EXPECT_FALSE(m[0].Number("time_s").has_value());
  EXPECT_EQ(m[0].Text("timestamp"), "0000-00-00T24:60:60Z");
  // A valid base-station time converts to UNIX time: 2007-05-14T19:57:39Z.
  const auto t = DecodeLines({"!AIVDM,1,1,,A,403OviQuMGCqWrRO9>E6fE700@GO,0*4D"});
  EXPECT_DOUBLE_EQ(*t.at(0).Number("time_s"), 1179172659.0);
}

// Random corruption of the real logs: byte flips, truncations, inserted and
// deleted characters, shuffled lines. Nothing may crash (run under ASan/UBSan in
// CI) and every rejection has a reason.
TEST(AisDecoderFuzzTest, RandomCorruptionOfRealLogsNeverCrashes) {
  if (NmeaDir().empty()) SPECHT_SKIP() << "no data dir";
  std::mt19937 rng(7);
  for (const char* name : {"gpsd-sample.aivdm", "gpsd-ais-nmea.log", "libais-test.aivdm", "pyais-nmea-sample.txt",
                           "signalk-nais400-merrimac.log"}) {
    std::vector<std::string> lines;
    std::ifstream in(NmeaDir() + "/" + name);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    for (int round = 0; round < 20; ++round) {
      std::vector<std::string> corrupt = lines;
      for (auto& l : corrupt) {
        if (l.empty() || rng() % 4 != 0) continue;
        const size_t at = rng() % l.size();
        switch (rng() % 4) {
          case 0:
            l[at] = static_cast<char>(rng() % 256);
            break;
          case 1:
            l.resize(at);
            break;
          case 2:
            l.insert(at, 1, static_cast<char>(32 + rng() % 95));
            break;
          default:
            l.erase(at, 1 + rng() % 8);
            break;
        }
      }
      std::shuffle(corrupt.begin(), corrupt.begin() + corrupt.size() / 3, rng);
      DecoderStats s;
      DecodeLines(corrupt, &s);
      for (const auto& [reason, n] : s.sentences.rejected) EXPECT_FALSE(reason.empty());
      EXPECT_GT(s.RejectedTotal(), 0) << name;
    }
  }
}

}  // namespace
}  // namespace specht::ais
