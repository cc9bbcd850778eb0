#pragma once
// Checks beyond dynamics_checks.hpp that the bicycle and quadrotor models run (any model's test
// may use them):
// - FastInterval / DualFI (the tracker's hot-path types) enclose point values and Jacobians,
// - the DualD2 field carries the exact Hessian (against central differences of the DualD
//   Jacobian) and the plain value and Jacobian in its lower layers,
// - the built plugin library loads through its C entry point (dlopen, as core's loader does).
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "dynamics_checks.hpp"
#include "marsyn/plugin.hpp"

namespace marsyn::testing {

// Random sub-boxes of `where`, random points (a third of them on the box faces) inside each:
// f(point) in F_fast(box), J(point) in J_fast(box).
inline void expect_fast_interval_encloses_points(const Dynamics& f, const SampleBox& where, int boxes = 300,
                                                 int points = 100) {
  const int n = f.state_dim(), m = f.input_dim();
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int b = 0; b < boxes; ++b) {
    std::vector<double> lo(n + m), hi(n + m);
    for (int i = 0; i < n + m; ++i) {
      const double a = where.lo[i] + unit(rng) * (where.hi[i] - where.lo[i]);
      const double w = unit(rng) * unit(rng) * (where.hi[i] - where.lo[i]) * 0.3;
      lo[i] = a;
      hi[i] = std::min(where.hi[i], a + w);
    }
    std::vector<FastInterval> xi(n), ui(m), fi(n);
    std::vector<DualFI> xdi(n), udi(m), fdi(n);
    for (int i = 0; i < n; ++i) {
      xi[i] = FastInterval(lo[i], hi[i]);
      xdi[i] = DualFI::variable(xi[i], i, n + m);
    }
    for (int j = 0; j < m; ++j) {
      ui[j] = FastInterval(lo[n + j], hi[n + j]);
      udi[j] = DualFI::variable(ui[j], n + j, n + m);
    }
    f.field(xi.data(), ui.data(), fi.data());
    f.field(xdi.data(), udi.data(), fdi.data());
    for (int p = 0; p < points; ++p) {
      std::vector<double> z(n + m);
      for (int i = 0; i < n + m; ++i) {
        const double r = unit(rng);
        z[i] = r < 0.15 ? lo[i] : r < 0.3 ? hi[i] : lo[i] + unit(rng) * (hi[i] - lo[i]);
      }
      std::vector<double> fz(n);
      f.field(z.data(), z.data() + n, fz.data());
      std::vector<DualD> xd(n), ud(m), dd(n);
      for (int i = 0; i < n; ++i) xd[i] = DualD::variable(z[i], i, n + m);
      for (int j = 0; j < m; ++j) ud[j] = DualD::variable(z[n + j], n + j, n + m);
      f.field(xd.data(), ud.data(), dd.data());
      for (int i = 0; i < n; ++i) {
        ASSERT_LE(fi[i].lower(), fz[i]) << "component " << i << " box " << b;
        ASSERT_GE(fi[i].upper(), fz[i]) << "component " << i << " box " << b;
        ASSERT_LE(fdi[i].v.lower(), fz[i]) << "DualFI value, component " << i << " box " << b;
        ASSERT_GE(fdi[i].v.upper(), fz[i]) << "DualFI value, component " << i << " box " << b;
        for (int j = 0; j < n + m; ++j) {
          const FastInterval J = fdi[i].derivative(j);
          ASSERT_LE(J.lower(), dd[i].derivative(j)) << "d f" << i << "/dz" << j << " box " << b;
          ASSERT_GE(J.upper(), dd[i].derivative(j)) << "d f" << i << "/dz" << j << " box " << b;
        }
      }
    }
  }
}

// At random points of `where`: the DualD2 evaluation's value is the plain value, its first layer
// the DualD Jacobian, and its second layer d2 f_i / dz_a dz_b agrees with central differences
// of the DualD Jacobian (and is symmetric).
inline void expect_hessian_matches_differenced_jacobian(const Dynamics& f, const SampleBox& where,
                                                        int samples = 100) {
  ASSERT_TRUE(f.has_second_order());
  const int n = f.state_dim(), m = f.input_dim(), w = n + m;
  std::mt19937_64 rng(17);
  auto jacobian = [&](const std::vector<double>& z, std::vector<DualD>& out) {
    std::vector<DualD> zd(w);
    for (int i = 0; i < w; ++i) zd[i] = DualD::variable(z[i], i, w);
    out.assign(n, DualD{});
    f.field(zd.data(), zd.data() + n, out.data());
  };
  for (int s = 0; s < samples; ++s) {
    std::vector<double> z(w);
    for (int i = 0; i < w; ++i) z[i] = std::uniform_real_distribution<double>(where.lo[i], where.hi[i])(rng);
    std::vector<DualD2> z2(w), f2(n);
    for (int i = 0; i < w; ++i) z2[i] = second_order_variable(z[i], i, w);
    f.field(z2.data(), z2.data() + n, f2.data());
    std::vector<DualD> J;
    jacobian(z, J);
    for (int i = 0; i < n; ++i) {
      EXPECT_DOUBLE_EQ(f2[i].v.v, J[i].v) << "value of f" << i << " at sample " << s;
      for (int a = 0; a < w; ++a) EXPECT_DOUBLE_EQ(f2[i].v.derivative(a), J[i].derivative(a));
    }
    for (int b = 0; b < w; ++b) {
      const double h = 1e-5 * std::max(1.0, std::abs(z[b]));
      auto zp = z, zm = z;
      zp[b] += h;
      zm[b] -= h;
      std::vector<DualD> Jp, Jm;
      jacobian(zp, Jp);
      jacobian(zm, Jm);
      for (int i = 0; i < n; ++i)
        for (int a = 0; a < w; ++a) {
          const double fd = (Jp[i].derivative(a) - Jm[i].derivative(a)) / (2 * h);
          const double H = second_derivative(f2[i], a, b);
          EXPECT_NEAR(H, fd, 1e-5 * std::max(1.0, std::abs(fd)))
              << "d2 f" << i << " / dz" << a << " dz" << b << " at sample " << s;
          EXPECT_DOUBLE_EQ(H, second_derivative(f2[i], b, a)) << "symmetry of d2 f" << i;
        }
    }
  }
}

// The built library, opened as core's loader opens it.
struct LoadedLibrary {
  void* handle = nullptr;
  const marsyn_plugin_manifest* manifest = nullptr;
  explicit LoadedLibrary(const std::string& path) {
    handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) return;
    using Entry = const marsyn_plugin_manifest* (*)();
    if (auto entry = reinterpret_cast<Entry>(dlsym(handle, "marsyn_plugin_entry_point"))) manifest = entry();
  }
  ~LoadedLibrary() {
    if (handle) dlclose(handle);
  }
  LoadedLibrary(const LoadedLibrary&) = delete;
  LoadedLibrary& operator=(const LoadedLibrary&) = delete;

  const marsyn_plugin_entry* find(const std::string& kind, const std::string& name) const {
    if (!manifest) return nullptr;
    for (std::size_t i = 0; i < manifest->entry_count; ++i)
      if (kind == manifest->entries[i].kind && name == manifest->entries[i].name) return &manifest->entries[i];
    return nullptr;
  }
  std::unique_ptr<Dynamics> create(const marsyn_plugin_entry& e, const Params& p) const {
    return std::unique_ptr<Dynamics>(static_cast<Dynamics*>(e.create(p)));
  }
};

// The same model built into the test and created by the library give bit-identical fields.
inline void expect_same_field(const Dynamics& a, const Dynamics& b, const SampleBox& where) {
  ASSERT_EQ(a.state_dim(), b.state_dim());
  ASSERT_EQ(a.input_dim(), b.input_dim());
  const int n = a.state_dim(), m = a.input_dim();
  std::mt19937_64 rng(19);
  for (int s = 0; s < 20; ++s) {
    std::vector<double> z(n + m), fa(n), fb(n);
    for (int i = 0; i < n + m; ++i) z[i] = std::uniform_real_distribution<double>(where.lo[i], where.hi[i])(rng);
    a.field(z.data(), z.data() + n, fa.data());
    b.field(z.data(), z.data() + n, fb.data());
    for (int i = 0; i < n; ++i) EXPECT_EQ(fa[i], fb[i]) << "component " << i << " at sample " << s;
  }
}

}  // namespace marsyn::testing
