#include <dualspectra/dualspectra.hpp>
#include <dualspectra/dualspectra.h>
#include <cmath>
#include <iostream>
int main() {
  std::vector<std::array<double,3>> V{{0,0,0},{1,0,0},{0,1,0},{0,0,1}};
  std::vector<std::array<uint32_t,3>> F{{0,2,1},{0,1,3},{0,3,2},{1,2,3}};
  dualspectra::Mesh m(V, F);
  auto K = dualspectra::gaussian_curvature(m);
  double s = 0; auto a = dualspectra::mass(m); for (size_t i = 0; i < K.size(); ++i) s += K[i]*a[i];
  std::cout << dualspectra::version() << " " << ds_version() << " Gauss-Bonnet sum K a = " << s << "\n";
  // Closed genus-0 surface: sum K_i a_i = 4 pi up to rounding.
  if (std::abs(s - 4 * 3.14159265358979323846) > 1e-12) return 1;
  try {
    dualspectra::Mesh bad(std::vector<double>{0, 0, 0}, std::vector<uint32_t>{0, 1, 2});
    return 1;
  } catch (const dualspectra::Error& e) {
    std::cout << "expected error, status " << static_cast<int>(e.status()) << ": " << e.what() << "\n";
    if (e.status() != dualspectra::Status::InvalidMesh) return 1;
  }
  return 0;
}
