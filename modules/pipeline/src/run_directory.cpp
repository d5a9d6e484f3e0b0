#include "specht/pipeline/run_directory.h"

#include "specht/io/atomic_file.h"

namespace specht::pipeline {

void PrepareRunDirectory(const std::string& dir, const params::Params& params) {
  io::MakeOutputDir(dir);
  io::WriteTextAtomically(dir + "/params.yaml",
                          "# effective parameters of this run (specht 0.1.0)\n" + params.ToYaml(true));
}

}  // namespace specht::pipeline
