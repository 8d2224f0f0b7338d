#pragma once

// Frees a container's memory at once, for buffers a stage is done with while larger ones are still
// to come: the peak of a dense scan's run is what its memory figure measures.
//
// `buffer = {}` does not do it: for a std::vector it picks operator=(initializer_list), which
// empties the vector and keeps its capacity until the vector is destroyed.

namespace clearway::detail {

template <typename Container>
void releaseMemory(Container& buffer) {
  Container().swap(buffer);
}

}  // namespace clearway::detail
