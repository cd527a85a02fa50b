// OpenMesh's stock Decimater as the benchmarks run it (header only):
// ModQuadric with no error limit plus ModAspectRatio 10, as OpenMesh's own
// tools set it up. bench_simplify times it; bench_fidelity judges its LODs.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <cstddef>

namespace perclod::bench {

struct DTraits : OpenMesh::DefaultTraits {
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
};
using DMesh = OpenMesh::TriMesh_ArrayKernelT<DTraits>;

// Decimates `mesh` (face normals up to date) towards `target` faces; deleted
// elements stay marked until the caller's garbage_collection().
inline void decimate_stock(DMesh& mesh, size_t target) {
  OpenMesh::Decimater::DecimaterT<DMesh> dec(mesh);
  OpenMesh::Decimater::ModQuadricT<DMesh>::Handle hq;
  OpenMesh::Decimater::ModAspectRatioT<DMesh>::Handle ha;
  dec.add(hq);
  dec.add(ha);
  dec.module(hq).unset_max_err();
  dec.module(ha).set_aspect_ratio(10.0f);
  dec.initialize();
  dec.decimate_to_faces(0, target);
}

}  // namespace perclod::bench
