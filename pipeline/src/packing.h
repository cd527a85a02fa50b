// Lossless packing of the buffers a job keeps between its stages (private):
// the judged views' colours and the labelling renders' triangle IDs. zlib at
// level 1: renders of buildings are large flat-shaded areas, so a 1280x1024
// view packs 15-180x in 5-25 ms and unpacks in 3-10 ms; the 86 views of the
// 1M facade at 56 m keep a few tens of MB instead of 335 MB of colours and
// 450 MB of IDs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace perclod::detail {

// The packed bytes of data[0, bytes).
std::vector<uint8_t> pack_bytes(const void* data, size_t bytes);
// Unpacks into out[0, bytes); throws std::logic_error unless `packed` holds
// exactly that many bytes.
void unpack_bytes(const std::vector<uint8_t>& packed, void* out, size_t bytes);

}  // namespace perclod::detail
