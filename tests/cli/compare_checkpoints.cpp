// Compares the particle state of two checkpoints bit for bit (positions, velocities, angular
// velocities, orientations, forces, torques, ids, and the contact history). Exit 0 when equal;
// otherwise prints the first difference and exits 1.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "src/hdf5_io.hpp"

namespace {

bool same_bits(const std::vector<double>& a, const std::vector<double>& b, std::size_t& first) {
  if (a.size() != b.size())
    return first = 0, false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (std::memcmp(&a[k], &b[k], sizeof(double)) != 0)
      return first = k, false;
  return true;
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: compare_checkpoints A.h5 B.h5\n");
    return 2;
  }
  const kdem::Hdf5Reader a(argv[1]), b(argv[2]);
  if (a.read_int64("particles/id") != b.read_int64("particles/id")) {
    std::printf("particle ids or order differ\n");
    return 1;
  }
  const char* fields[] = {"particles/position",
                          "particles/velocity",
                          "particles/angular_velocity",
                          "particles/orientation",
                          "particles/force",
                          "particles/torque",
                          "pairs/tangential_spring",
                          "wall_contacts/tangential_spring"};
  for (const char* field : fields) {
    std::size_t first = 0;
    const auto va = a.read_doubles(field), vb = b.read_doubles(field);
    if (!same_bits(va, vb, first)) {
      std::printf("%s differs (sizes %zu, %zu; first index %zu: %.17g vs %.17g)\n", field,
                  va.size(), vb.size(), first, first < va.size() ? va[first] : 0.0,
                  first < vb.size() ? vb[first] : 0.0);
      return 1;
    }
  }
  if (a.read_scalar_double("time") != b.read_scalar_double("time")) {
    std::printf("times differ\n");
    return 1;
  }
  std::printf("identical: %zu particles\n", a.read_int64("particles/id").size());
  return 0;
}
