// Lossless packing of the buffers a job keeps between its stages (private):
// the judged views' colours and the labelling renders' triangle IDs. zlib at
// level 1: renders of buildings are large flat-shaded areas, so the colours
// of a 1280x1024 tile of the 1M facade pack 16-180x (3.9 MB to 22-240 KB)
// in 7-24 ms and unpack in 3-9 ms. Unpacked, the 86 judged tiles at 56 m
// held 335 MB of colours and the 52 labelling tiles 450 MB of IDs; packing
// both took the run's peak from 1,004 to 744 MiB.
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
