// SPDX-License-Identifier: MIT
// Paper P4's level-1 DWT (dwt.hpp) against PyWavelets run at test time: the filters bit for
// bit, pywt.dwt and pywt.idwt ('periodization' and 'symmetric') to 1e-12 on seeded blocks;
// perfect reconstruction; the soft threshold (eq 16), the universal threshold (eq 17) and the
// MAD noise estimate by hand; refusals of bad input.
// The reference is reference/pywt_vectors.py, run with NAV_SYSTEM_PYTHON3 (Debian's
// /usr/bin/python3 with python3-pywt; CMake finds it). Without it the test fails, it does not
// skip: run scripts/setup.
#include "nav/estimator/dwt.hpp"
#include "source_paths.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace nav::estimator {
namespace {

constexpr double kTol = 1e-12;
constexpr Wavelet kWavelets[] = {Wavelet::kHaar, Wavelet::kDb4, Wavelet::kSym4};
constexpr DwtMode kModes[] = {DwtMode::kPeriodization, DwtMode::kSymmetric};

// Seeded blocks: short ones (shorter than the filter, odd) exercise the boundary rules.
std::map<std::string, Eigen::VectorXd> make_signals() {
  std::mt19937_64 rng(20130304);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::map<std::string, Eigen::VectorXd> s;
  for (const int n : {1, 2, 3, 7, 16, 17, 64}) {
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) {
      x(i) = 3.0 * n01(rng) + 0.01 * i;
    }
    s["s" + std::to_string(n)] = x;
  }
  return s;
}

struct Bands {
  Eigen::VectorXd cA;
  Eigen::VectorXd cD;
};

std::map<std::string, Bands> make_bands() {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::map<std::string, Bands> b;
  for (const int m : {1, 3, 4, 5, 8, 32}) {
    Bands p{Eigen::VectorXd(m), Eigen::VectorXd(m)};
    for (int k = 0; k < m; ++k) {
      p.cA(k) = u(rng);
      p.cD(k) = u(rng);
    }
    b["b" + std::to_string(m)] = p;
  }
  return b;
}

void write_values(std::ostream& os, const Eigen::VectorXd& v) {
  char buf[40];
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    std::snprintf(buf, sizeof buf, " %.17g", v(i));  // reads back as the same double
    os << buf;
  }
}

// pywt's answers, keyed by the OUTPUT line's words before the values.
class PywtReference {
 public:
  static const PywtReference& get() {
    static const PywtReference ref;
    return ref;
  }
  const std::string& failure() const { return failure_; }
  // Values of a line, or empty (with a test failure) when pywt did not print it.
  std::vector<double> values(const std::string& key) const {
    const auto it = lines_.find(key);
    if (it == lines_.end()) {
      ADD_FAILURE() << "pywt printed no line '" << key << "'";
      return {};
    }
    return it->second;
  }

 private:
  PywtReference() {
    const std::string python = NAV_SYSTEM_PYTHON3;
    if (python.empty() || python.find("NOTFOUND") != std::string::npos ||
        !std::filesystem::exists(python)) {
      failure_ = "no system python3 (NAV_SYSTEM_PYTHON3='" + python +
                 "'): run scripts/setup, which installs python3-pywt for /usr/bin/python3";
      return;
    }
    const auto dir = std::filesystem::temp_directory_path() /
                     ("nav_p4_dwt_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto in = dir / "input.txt";
    const auto out = dir / "pywt.txt";
    {
      std::ofstream f(in);
      for (const auto& [name, x] : make_signals()) {
        f << "signal " << name;
        write_values(f, x);
        f << "\n";
      }
      for (const auto& [name, b] : make_bands()) {
        f << "bands " << name << " " << b.cA.size();
        write_values(f, b.cA);
        write_values(f, b.cD);
        f << "\n";
      }
    }
    const std::string script =
        nav::test_paths::source_dir() + "/tests/unit/estimator/reference/pywt_vectors.py";
    const std::string cmd = "'" + python + "' '" + script + "' '" + in.string() + "' '" +
                            out.string() + "' 2>&1";
    std::string said;
    int status = -1;
    if (FILE* p = ::popen(cmd.c_str(), "r")) {
      char buf[512];
      while (std::fgets(buf, sizeof buf, p) != nullptr) {
        said += buf;
      }
      const int wait_status = ::pclose(p);
      status = WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : -1;
    }
    if (status != 0) {
      failure_ = "'" + cmd + "' failed (exit " + std::to_string(status) + "): " + said +
                 "\nPyWavelets is needed by this test: run scripts/setup (python3-pywt)";
      std::filesystem::remove_all(dir);
      return;
    }
    std::ifstream f(out);
    for (std::string line; std::getline(f, line);) {
      std::istringstream is(line);
      std::string key;
      std::vector<double> v;
      for (std::string w; is >> w;) {
        char* end = nullptr;
        const double d = std::strtod(w.c_str(), &end);
        if (end != w.c_str() && *end == '\0') {
          v.push_back(d);
        } else {
          key += (key.empty() ? "" : " ") + w;
        }
      }
      lines_[key] = v;
    }
    std::filesystem::remove_all(dir);
    if (lines_.empty()) {
      failure_ = "pywt_vectors.py wrote nothing: " + said;
    }
  }
  std::string failure_;
  std::map<std::string, std::vector<double>> lines_;
};


void expect_near_vector(const Eigen::VectorXd& got, const std::vector<double>& want,
                        const std::string& what) {
  ASSERT_EQ(static_cast<std::size_t>(got.size()), want.size()) << what;
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_NEAR(got(static_cast<Eigen::Index>(i)), want[i], kTol) << what << " [" << i << "]";
  }
}

// "dwt sym4 periodization s16 cA": the words of a pywt_vectors.py OUTPUT line before its values.
std::string key(const char* what, Wavelet w, DwtMode m, const std::string& rest) {
  return std::string(what) + " " + to_string(w) + " " + to_string(m) + " " + rest;
}

// GIVEN pywt.Wavelet(name) WHEN the filter banks are built THEN all four filters are pywt's,
// bit for bit (17-digit literals).
TEST(P4Dwt, FiltersArePywtsBitForBit) {
  const PywtReference& ref = PywtReference::get();
  ASSERT_TRUE(ref.failure().empty()) << ref.failure();  // fails, never skips, without pywt
  for (const Wavelet w : kWavelets) {
    const FilterBank fb = filter_bank(w);
    const std::pair<const char*, const FilterTaps*> kinds[] = {
        {"dec_lo", &fb.dec_lo}, {"dec_hi", &fb.dec_hi}, {"rec_lo", &fb.rec_lo},
        {"rec_hi", &fb.rec_hi}};
    for (const auto& [kind, taps] : kinds) {
      const std::vector<double> want =
          ref.values(std::string("filter ") + to_string(w) + " " + kind);
      ASSERT_EQ(want.size(), static_cast<std::size_t>(fb.length)) << to_string(w) << kind;
      for (int n = 0; n < fb.length; ++n) {
        EXPECT_EQ((*taps)[n], want[n]) << to_string(w) << " " << kind << " [" << n << "]";
      }
    }
  }
}

// THEN the quadrature-mirror relation g(L−1−n) = (−1)ⁿ h(n) (P4 eq 13, W2) holds with
// h = dec_lo (low-pass) and g = dec_hi (high-pass), and the filters are orthonormal:
// Σh = √2, Σg = 0, Σh² = 1, Σ h(n) h(n+2) = 0: to 1e-15 for haar and db4, but only to ~1e-12
// for pywt's sym4 (Σg = −1.13e-12, Σh² − 1 = 4.9e-13: the tabulated digits), which the bit-for-
// bit match above inherits.
TEST(P4Dwt, QuadratureMirrorPairIsOrthonormal) {
  for (const Wavelet w : kWavelets) {
    const FilterBank fb = filter_bank(w);
    const int L = fb.length;
    const double tol = w == Wavelet::kSym4 ? 2e-12 : 1e-15;
    double sum_h = 0.0, sum_g = 0.0, energy = 0.0;
    for (int n = 0; n < L; ++n) {
      EXPECT_EQ(fb.dec_hi[L - 1 - n], (n % 2 == 0 ? 1.0 : -1.0) * fb.dec_lo[n]);
      sum_h += fb.dec_lo[n];
      sum_g += fb.dec_hi[n];
      energy += fb.dec_lo[n] * fb.dec_lo[n];
    }
    EXPECT_NEAR(sum_h, std::sqrt(2.0), tol) << to_string(w);
    EXPECT_NEAR(sum_g, 0.0, tol) << to_string(w);
    EXPECT_NEAR(energy, 1.0, tol) << to_string(w);
    for (int shift = 2; shift < L; shift += 2) {
      double c = 0.0;
      for (int n = 0; n + shift < L; ++n) {
        c += fb.dec_lo[n] * fb.dec_lo[n + shift];
      }
      EXPECT_NEAR(c, 0.0, tol) << to_string(w) << " shift " << shift;
    }
  }
}

// GIVEN seeded blocks of 1..64 samples WHEN dwt THEN cA, cD equal pywt.dwt's (1e-12).
TEST(P4Dwt, AnalysisMatchesPywt) {
  const PywtReference& ref = PywtReference::get();
  ASSERT_TRUE(ref.failure().empty()) << ref.failure();  // fails, never skips, without pywt
  for (const auto& [name, x] : make_signals()) {
    for (const Wavelet w : kWavelets) {
      for (const DwtMode m : kModes) {
        const Result<DwtCoefficients> c = dwt(x, w, m);
        ASSERT_TRUE(c.has_value()) << c.error().detail;
        EXPECT_EQ(static_cast<std::size_t>(c->cA.size()),
                  dwt_coefficient_count(static_cast<std::size_t>(x.size()), w, m));
        expect_near_vector(c->cA, ref.values(key("dwt", w, m, name + " cA")),
                           key("dwt", w, m, name + " cA"));
        expect_near_vector(c->cD, ref.values(key("dwt", w, m, name + " cD")),
                           key("dwt", w, m, name + " cD"));
      }
    }
  }
}

// GIVEN seeded bands of 1..32 coefficients WHEN idwt THEN x equals pywt.idwt's (1e-12); bands
// too short for 'symmetric' are refused (pywt is not asked for them).
TEST(P4Dwt, SynthesisMatchesPywt) {
  const PywtReference& ref = PywtReference::get();
  ASSERT_TRUE(ref.failure().empty()) << ref.failure();  // fails, never skips, without pywt
  for (const auto& [name, b] : make_bands()) {
    for (const Wavelet w : kWavelets) {
      for (const DwtMode m : kModes) {
        const Result<Eigen::VectorXd> x = idwt(b.cA, b.cD, w, m);
        const long n_sym = 2 * b.cA.size() - filter_bank(w).length + 2;
        if (m == DwtMode::kSymmetric && n_sym < 1) {
          EXPECT_FALSE(x.has_value()) << key("idwt", w, m, name);
          continue;
        }
        ASSERT_TRUE(x.has_value()) << x.error().detail;
        expect_near_vector(*x, ref.values(key("idwt", w, m, name)), key("idwt", w, m, name));
      }
    }
  }
}

// GIVEN any block WHEN idwt(dwt(x)) THEN x again (orthogonal filters; 'symmetric' returns one
// extra sample for odd lengths, as pywt); denoise() with a fixed λ = 0 returns x. To 1e-12
// relative to max|x|, 5e-12 for sym4: pywt's sym4 taps are orthonormal to ~1e-12 only
// (QuadratureMirrorPairIsOrthonormal), and blocks shorter than the filter wrap it (s3: 1.1e-12).
TEST(P4Dwt, PerfectReconstruction) {
  for (const auto& [name, x] : make_signals()) {
    for (const Wavelet w : kWavelets) {
      const double tol =
          (w == Wavelet::kSym4 ? 5e-12 : kTol) * std::max(1.0, x.cwiseAbs().maxCoeff());
      for (const DwtMode m : kModes) {
        const Result<DwtCoefficients> c = dwt(x, w, m);
        ASSERT_TRUE(c.has_value());
        const Result<Eigen::VectorXd> y = idwt(c->cA, c->cD, w, m);
        ASSERT_TRUE(y.has_value()) << key("idwt", w, m, name) << ": " << y.error().detail;
        ASSERT_GE(y->size(), x.size());
        EXPECT_LE((y->head(x.size()) - x).cwiseAbs().maxCoeff(), tol) << key("dwt", w, m, name);
      }
      if (x.size() % 2 == 0) {
        const Result<DwtDenoised> d = denoise(x, w, {ThresholdRule::kFixed, 0.0});
        ASSERT_TRUE(d.has_value()) << d.error().detail;
        EXPECT_LE((d->x - x).cwiseAbs().maxCoeff(), tol) << name;
        EXPECT_EQ(d->lambda, 0.0);
      }
    }
  }
}

// Soft threshold (P4 eq 16, W8) on hand-picked values.
TEST(P4Dwt, SoftThresholdByHand) {
  EXPECT_EQ(soft_threshold(3.0, 1.0), 2.0);
  EXPECT_EQ(soft_threshold(-3.0, 1.0), -2.0);   // u − sign(u)·λ = −3 + 1
  EXPECT_EQ(soft_threshold(0.5, 1.0), 0.0);     // |u| < λ
  EXPECT_EQ(soft_threshold(-0.999, 1.0), 0.0);
  EXPECT_EQ(soft_threshold(1.0, 1.0), 0.0);     // |u| = λ: both branches give 0
  EXPECT_EQ(soft_threshold(-1.0, 1.0), 0.0);
  EXPECT_EQ(soft_threshold(1.25, 0.0), 1.25);   // λ = 0: unchanged
  EXPECT_EQ(soft_threshold(-1.25, 0.0), -1.25);
  EXPECT_EQ(soft_threshold(0.0, 0.0), 0.0);
  EXPECT_EQ(soft_threshold(0.75, 0.5), 0.25);
}

// Universal threshold (P4 eq 17, W9) and the MAD noise estimate (W10), by hand.
TEST(P4Dwt, UniversalThresholdByHand) {
  // n = e²: √(2 ln n) = 2, so λ = 2σ.
  EXPECT_NEAR(universal_threshold(0.3, std::exp(2.0)), 0.6, 1e-15);
  // n = 64: 2 ln 64 = 12 ln 2 = 8.317766166719343, √ = 2.884053773201766; σ = 0.5 →
  // λ = 1.442026886600883.
  EXPECT_NEAR(universal_threshold(0.5, 64.0), 1.442026886600883, 1e-14);
  EXPECT_EQ(universal_threshold(0.7, 1.0), 0.0);  // ln 1 = 0
  // |d| sorted: 0.1 0.3 0.6745 2 5 → median 0.6745 → σ̂ = 1 (the sign of d does not matter).
  const std::vector<double> d = {-5.0, 0.3, 0.6745, -0.1, 2.0};
  std::vector<double> scratch(d.size());
  EXPECT_NEAR(mad_noise_std(d, scratch), 1.0, 1e-15);
  // Even count: median = mean of the two middle |d| (0.3, 0.6745 → 0.48725) / 0.6745.
  const std::vector<double> d4 = {0.3, -0.6745, 9.0, 0.1};
  EXPECT_NEAR(mad_noise_std(d4, scratch), 0.48725 / 0.6745, 1e-15);
  // Interior detail coefficients of a 64-sample 'periodization' block (W10): sym4 k = 2..29,
  // haar all 32.
  EXPECT_EQ(interior_coefficients(64, 8).first, 2);
  EXPECT_EQ(interior_coefficients(64, 8).last, 30);
  EXPECT_EQ(interior_coefficients(64, 2).first, 0);
  EXPECT_EQ(interior_coefficients(64, 2).last, 32);
}

// GIVEN a block whose interior details are known WHEN denoise with the universal rule THEN λ
// is σ̂ √(2 ln n) with σ̂ from the interior details only.
TEST(P4Dwt, DenoiseUsesInteriorMadAndBlockLength) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  Eigen::VectorXd x(64);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x(i) = 10.0 * static_cast<double>(i) / 64.0 + 0.1 * n01(rng);  // a ramp: a jump at the wrap
  }
  const Result<DwtDenoised> d = denoise(x, Wavelet::kSym4, {});
  ASSERT_TRUE(d.has_value());
  const Result<DwtCoefficients> c = dwt(x, Wavelet::kSym4, DwtMode::kPeriodization);
  std::vector<double> interior(c->cD.data() + 2, c->cD.data() + 30);
  std::vector<double> scratch(interior.size());
  const double sigma = mad_noise_std(interior, scratch);
  EXPECT_EQ(d->sigma, sigma);
  EXPECT_EQ(d->lambda, universal_threshold(sigma, 64.0));
  EXPECT_LT(d->sigma, 0.2);  // the wrap's jump (10) did not enter σ̂
}

// Refusals: values, never a throw or an abort.
TEST(P4Dwt, RefusesBadInput) {
  const double nan = std::nan("");
  EXPECT_FALSE(dwt(Eigen::VectorXd(), Wavelet::kDb4, DwtMode::kSymmetric).has_value());
  EXPECT_FALSE(dwt(Eigen::VectorXd::Constant(8, nan), Wavelet::kDb4, DwtMode::kPeriodization)
                   .has_value());
  Eigen::VectorXd inf = Eigen::VectorXd::Zero(8);
  inf(3) = INFINITY;
  EXPECT_FALSE(dwt(inf, Wavelet::kHaar, DwtMode::kSymmetric).has_value());
  EXPECT_FALSE(idwt(Eigen::VectorXd::Zero(4), Eigen::VectorXd::Zero(5), Wavelet::kSym4,
                    DwtMode::kPeriodization).has_value());
  EXPECT_FALSE(idwt(Eigen::VectorXd::Zero(4), inf.head(4), Wavelet::kSym4,
                    DwtMode::kPeriodization).has_value());
  const Result<Eigen::VectorXd> short_sym =
      idwt(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3), Wavelet::kSym4,
           DwtMode::kSymmetric);
  ASSERT_FALSE(short_sym.has_value());
  EXPECT_EQ(short_sym.error().code, ErrorCode::kInvalidArgument);
  EXPECT_FALSE(denoise(Eigen::VectorXd::Zero(15), Wavelet::kSym4, {}).has_value());  // odd
  EXPECT_FALSE(denoise(Eigen::VectorXd::Zero(14), Wavelet::kSym4, {}).has_value());  // < 2L
  EXPECT_FALSE(denoise(inf, Wavelet::kHaar, {}).has_value());
  EXPECT_FALSE(denoise(Eigen::VectorXd::Zero(8), Wavelet::kHaar,
                       {ThresholdRule::kFixed, -1.0}).has_value());
  EXPECT_FALSE(denoise(Eigen::VectorXd::Zero(8), Wavelet::kHaar,
                       {ThresholdRule::kFixed, nan}).has_value());
}

}  // namespace
}  // namespace nav::estimator
