// datasets/manifest.yaml: every dataset it names is where it says, with its checksum.
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>

#include "test_support.h"

namespace specht {
namespace {

std::string Sha256(const std::string& path) {
  const std::string cmd = "sha256sum '" + path + "'";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return "";
  char buf[65] = {0};
  const size_t n = fread(buf, 1, 64, pipe);
  pclose(pipe);
  return std::string(buf, n);
}

TEST(ManifestTest, EveryListedFileExistsWithItsChecksum) {
  const YAML::Node manifest = YAML::LoadFile(testing::SourceDir() + "/datasets/manifest.yaml");
  const std::string data = testing::DataDir();
  int checked = 0;
  for (const auto& d : manifest["datasets"]) {
    ASSERT_TRUE(d["name"] && d["format"] && d["source"] && d["licence"] && d["path"]) << d;
    const std::string path = d["path"].as<std::string>();
    const bool absolute = path.front() == '/';
    if (!absolute && data.empty()) continue;  // evaluation data not here
    const std::string full = absolute ? path : data + "/" + path;
    if (!std::filesystem::exists(full)) {
      ADD_FAILURE() << d["name"] << ": " << full << " is missing";
      continue;
    }
    const YAML::Node sha = d["sha256"];
    if (sha.IsScalar()) {
      EXPECT_EQ(Sha256(full), sha.as<std::string>()) << full;
      ++checked;
    } else {
      for (const auto& kv : sha) {
        EXPECT_EQ(Sha256(full + "/" + kv.first.as<std::string>()), kv.second.as<std::string>());
        ++checked;
      }
    }
  }
  EXPECT_GE(checked, 3);
}

}  // namespace
}  // namespace specht
