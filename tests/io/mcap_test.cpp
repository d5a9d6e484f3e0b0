// MCAP files (io/mcap.h): what the writer writes the reader reads back in order,
// across chunks; a cut file yields what lies before the cut and then names the byte;
// a chunk compressed with what we cannot read is named. (That Foxglove's own readers
// open our files is SlamCliTest.WritesAnMcap…, with @mcap/core.)
#include "specht/io/mcap.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "specht/io/dataset.h"
#include "test_support.h"

namespace specht::io {
namespace {

using ::testing::HasSubstr;

// 600 messages on two channels, chunks of 4 KB: many chunks.
std::string WriteSample(const std::string& dir) {
  const std::string path = dir + "/sample.mcap";
  McapWriter w(path, 4096);
  const uint16_t schema = w.AddSchema("std_msgs/msg/String", "ros2msg", "string data\n");
  const uint16_t a = w.AddChannel(schema, "/a", "cdr"), b = w.AddChannel(schema, "/b", "cdr");
  for (int i = 0; i < 600; ++i) w.Write(i % 3 ? a : b, 1000 + i, std::vector<uint8_t>(20 + i % 7, uint8_t(i)));
  EXPECT_FALSE(std::filesystem::exists(path));  // under a temporary name until closed
  w.Close();
  EXPECT_TRUE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(dir + "/sample.tmp.mcap"));
  return path;
}

TEST(McapTest, WhatIsWrittenReadsBackInOrderAcrossChunks) {
  const std::string path = WriteSample(testing::TempDir("mcap_roundtrip"));
  McapReader r(path);
  int i = 0;
  while (auto m = r.Next()) {
    EXPECT_EQ(m->topic, i % 3 ? "/a" : "/b");
    EXPECT_EQ(m->schema_name, "std_msgs/msg/String");
    EXPECT_EQ(m->log_time_ns, 1000u + i);
    EXPECT_EQ(m->data, std::vector<uint8_t>(20 + i % 7, uint8_t(i)));
    ++i;
  }
  EXPECT_EQ(i, 600);
  EXPECT_EQ(r.profile(), "ros2");
}

TEST(McapTest, ACutFileYieldsWhatLiesBeforeTheCutThenNamesTheByte) {
  const std::string dir = testing::TempDir("mcap_cut");
  const std::string bytes = testing::ReadFile(WriteSample(dir));
  testing::WriteFile(dir + "/cut.mcap", bytes.substr(0, bytes.size() / 2));
  McapReader r(dir + "/cut.mcap");
  int read = 0;
  try {
    while (r.Next()) ++read;
    FAIL() << "no error";
  } catch (const DatasetError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cut.mcap: record"));
    EXPECT_THAT(e.what(), HasSubstr("truncated"));
  }
  EXPECT_GT(read, 100);  // the whole chunks before the cut
  EXPECT_LT(read, 600);
}

TEST(McapTest, AnUnknownCompressionOrNoMagicIsNamed) {
  const std::string dir = testing::TempDir("mcap_bad");
  std::string bytes = testing::ReadFile(WriteSample(dir));
  bytes.replace(bytes.find("zstd"), 4, "zzzz");
  testing::WriteFile(dir + "/odd.mcap", bytes);
  McapReader r(dir + "/odd.mcap");
  try {
    while (r.Next()) {
    }
    FAIL() << "no error";
  } catch (const DatasetError& e) {
    EXPECT_THAT(e.what(), HasSubstr("a chunk compressed with 'zzzz', which is not read"));
  }
  testing::WriteFile(dir + "/not.mcap", "hello, world");
  EXPECT_THROW(McapReader(dir + "/not.mcap"), InputError);
}

}  // namespace
}  // namespace specht::io
