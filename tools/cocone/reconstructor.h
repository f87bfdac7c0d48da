// The Cocone reconstructor's state, shared by the files that implement its steps
// (private to tools/cocone; CGAL stays inside this stage library). Steps and their files:
//   reconstruct.cpp  deduplicate -> Delaunay triangulation (flat arrays) -> circumcentres; run()
//   candidates.cpp   poles -> cocone test per Delaunay facet -> Dey–Giesen flatness -> candidates
//   complex.cpp      candidate complex -> umbrellas -> pruning of sharp edges -> manifold walk
//   orient.cpp       oriented facets -> non-manifold edges -> per-component orientation
#pragma once

#include <Eigen/Core>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <array>
#include <cstdint>
#include <vector>

#include "cocone/cocone.h"

namespace canopy::cocone::detail {

using K = CGAL::Epick;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<int, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<int, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Sequential_tag>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;
using Point = K::Point_3;
using V3 = Eigen::Vector3d;

constexpr int kInfinite = -1;

// The triangulation as flat arrays. Cell c has vertices cv[4c+k] (kInfinite for the infinite
// vertex), neighbours nbr[4c+k] (opposite vertex k) and nbri[4c+k] = index of c in that
// neighbour.
struct Flat {
  int cells = 0;
  std::vector<int> cv, nbr;
  std::vector<std::int8_t> nbri;
  bool finite(int c) const {
    return cv[4 * c] >= 0 && cv[4 * c + 1] >= 0 && cv[4 * c + 2] >= 0 && cv[4 * c + 3] >= 0;
  }
  int local(int c, int v) const {
    for (int k = 0; k < 4; ++k)
      if (cv[4 * c + k] == v) return k;
    return -1;
  }
};

// A finite Delaunay triangle, stored once: cell c, facet index i; v = its vertices in local
// order (i+1, i+2, i+3) mod 4.
struct Facet {
  int c;
  int i;
  int v[3];
};

inline V3 to_v3(const Point& p) { return V3(p.x(), p.y(), p.z()); }

class Reconstructor {
 public:
  Reconstructor(const std::vector<Eigen::Vector3d>& input, const std::vector<V3>& normals,
                const CoconeParams& params)
      : input_(input), normals_(normals), prm_(params) {}

  Surface run();

 private:
  void deduplicate();
  void triangulate();
  void poles();
  void cocone_tests();
  void flatness();
  void candidates();
  void build_complex();
  bool umbrella(int v) const;
  void prune();
  void walk();
  std::vector<Face> oriented_facets() const;
  std::vector<double> component_scores(const std::vector<Face>& faces, const std::vector<std::uint8_t>& drop,
                                       const std::vector<int>& comp, int ncomp) const;
  Surface finish();

  // --- data ---
  const std::vector<Eigen::Vector3d>& input_;
  const std::vector<V3>& normals_;
  CoconeParams prm_;
  ReconstructStats st_;

  std::vector<int> row_of_;  // unique point id -> input row (first occurrence)
  std::vector<V3> p_;        // unique points
  std::vector<Point> cp_;
  Flat t_;
  std::vector<V3> cc_;     // circumcentre per finite cell
  std::vector<V3> hulln_;  // per infinite cell: outward unit normal of its finite facet
  std::vector<V3> axis_;   // unit pole axis per vertex
  std::vector<std::uint8_t> axis_ok_, on_hull_;
  std::vector<double> height2_;  // squared negative-pole distance (-1: none)
  std::vector<double> width2_;   // squared co-polygon width (inf: unbounded in the cocone)
  std::vector<Facet> facets_;
  std::vector<int> fidx_;            // 4c+i -> facet index or -1
  std::vector<std::uint8_t> meets_;  // per facet: bit s set when e_t meets the cocone of v[s]
  std::vector<std::uint8_t> flat_;
  std::vector<std::uint8_t> alive_;  // candidate flag per facet
  // candidate complex
  std::vector<int> cand_;  // candidate facet ids (ascending)
  std::vector<std::array<int, 2>> edges_;
  std::vector<int> edge_off_, edge_fac_;   // edge -> incident candidate facets
  std::vector<std::array<int, 3>> fedge_;  // facet -> edge opposite slot s (only candidates)
  std::vector<int> vf_off_, vf_fac_;       // vertex -> incident candidate facets
  std::vector<std::uint8_t> umb_, removable_;
  // walk
  std::vector<int> comp_, front_;
  std::vector<int> order_;  // accepted facets in acceptance order
  int components_ = 0;
};

}  // namespace canopy::cocone::detail
