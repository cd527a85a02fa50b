// zlib behind pack_bytes / unpack_bytes (packing.h).
#include "perclod/packing.h"

#include <zlib.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace perclod::detail {

std::vector<uint8_t> pack_bytes(const void* data, size_t bytes) {
  if (bytes > std::numeric_limits<uLong>::max()) throw std::length_error("pack_bytes: buffer too large");
  uLongf size = compressBound(uLong(bytes));
  std::vector<uint8_t> packed(size);
  if (compress2(packed.data(), &size, static_cast<const Bytef*>(data), uLong(bytes), 1) != Z_OK)
    throw std::runtime_error("pack_bytes: zlib failed");
  packed.resize(size);
  packed.shrink_to_fit();  // the bound is the size unpacked and more
  return packed;
}

void unpack_bytes(const std::vector<uint8_t>& packed, void* out, size_t bytes) {
  uLongf size = uLongf(bytes);
  const int rc = uncompress(static_cast<Bytef*>(out), &size, packed.data(), uLong(packed.size()));
  if (rc != Z_OK || size != bytes)
    throw std::logic_error("unpack_bytes: packed buffer does not hold " + std::to_string(bytes) + " bytes (zlib " +
                           std::to_string(rc) + ")");
}

}  // namespace perclod::detail
