#include "clearway/memory_tuning.h"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace clearway {

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  // 32 MB is the largest threshold glibc accepts on 64-bit systems (mallopt refuses more).
  constexpr int kKeptBlockBytes = 32 * 1024 * 1024;
  mallopt(M_MMAP_THRESHOLD, kKeptBlockBytes);
  mallopt(M_TRIM_THRESHOLD, 8 * kKeptBlockBytes);
#endif
}

}  // namespace clearway
