// Handing freed memory back to the system (perclod/runtime.h).
#include "perclod/runtime.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace perclod::detail {

void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace perclod::detail
