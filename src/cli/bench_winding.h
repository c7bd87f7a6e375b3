#pragma once
/// `rayproof bench contains --open`: the generalized winding number on meshes that are not closed,
/// beside a brute-force double winding number and the closed mesh's exact contains.
#include <cstddef>
#include <string>
#include <vector>

namespace rayproof::cli {

/// Measures every mesh of `paths` (a closed one with 1% of its triangles removed, seeded), one
/// thread; `closed_reference` (a closed mesh, may be empty) gives the rate of contains to compare
/// with. Appends the target lines to `verdicts`; returns the number of wrong answers (contains against
/// the brute force where it is at least 1e-6 from 1/2).
std::size_t bench_open_meshes(const std::vector<std::string>& paths, const std::string& closed_reference, std::size_t points,
                              int repeat, std::vector<std::string>& verdicts);

}  // namespace rayproof::cli
