#pragma once

// One function per clearway-cli command. Each returns the process exit code: 0 success, 1 the
// work failed (bad file, device error); usage mistakes throw UsageError (exit 2).

#include <string>
#include <vector>

namespace clearway::cli {

// `--rings N` (info, segment, bench): the most beams a multi-beam LiDAR has (Ouster: 128).
inline constexpr long kMaxRings = 512;

int runInfo(const std::vector<std::string>& words);
int runSimulate(const std::vector<std::string>& words);
int runScene(const std::vector<std::string>& words);
int runEval(const std::vector<std::string>& words);
int runSegment(const std::vector<std::string>& words);
int runEmulate(const std::vector<std::string>& words);
int runAcquire(const std::vector<std::string>& words);
int runRemoteAcquire(const std::vector<std::string>& words);  // acquire --remote
int runServe(const std::vector<std::string>& words);
int runBench(const std::vector<std::string>& words);

}  // namespace clearway::cli
