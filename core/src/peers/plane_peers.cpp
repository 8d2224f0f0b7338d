#include "clearway/peers/plane_peers.h"

namespace clearway::peers {
namespace {

std::string needsOrganisedScan(const Scan& scan) {
  return scan.isOrganised() ? std::string()
                            : "needs an organised scan (lines of equal length); this one is not";
}

std::string runsOnAnyScan(const Scan&) {
  return {};
}

}  // namespace

const std::vector<PlanePeer>& planePeers() {
  static const std::vector<PlanePeer> peers = {
      {"pcl_organized_multiplane", needsOrganisedScan, pclOrganizedMultiPlane},
      {"pcl_region_growing", runsOnAnyScan, pclRegionGrowing},
      {"pcl_ransac_multiplane", runsOnAnyScan, pclRansacPlanes},
  };
  return peers;
}

}  // namespace clearway::peers
