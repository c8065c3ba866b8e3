// Spectrum fit: round trips over the paper's parameter ranges (noise-free and noisy, with the
// reported uncertainty checked against the actual error), the specular and extended terms,
// bad input, and the measured spectra the paper compares against (Fig. 9).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "../temp_dir.hpp"
#include "report_measured.hpp"
#include "skin/fit/fit.hpp"
#include "skin/fit/measured.hpp"
#include "skin/util/error.hpp"

#include "test_params.hpp"
#include "skin_test_paths.hpp"
#include "test_support.hpp"

using namespace skin::fit;

namespace {
MeasuredSpectrum synthetic(const skin::physics::SkinParameters& p, const SpectrumFitOptions& o, double sigma = 0,
                           unsigned seed = 1) {
  MeasuredSpectrum m;
  m.name = "synthetic";
  for (double l = 400; l <= 700; l += 2) m.wavelength_nm.push_back(l);
  m.R = model_reflectance(p, m.wavelength_nm, o);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
  if (sigma > 0)
    for (double& r : m.R) r = std::clamp(r + noise(rng), 0.0, 1.0);
  return m;
}
using skin_test::params;
}  // namespace

// Noise-free round trip over a grid spanning the paper's ranges (Figs 3-5, 7: C_m 0.1-50 %,
// beta_m 0-1, C_h 0.1-20 %). Tolerance: the fit must reproduce the spectrum to 1e-5 RMS and the
// parameters to 2 % (relative) or 0.02 (beta_m, absolute); where melanin hides the dermis
// (C_m >= 0.3) C_h is only weakly identifiable and its tolerance is 15 %.
TEST(SpectrumFit, RoundTripNoiseFree) {
  const SpectrumFitter fitter(skin_test::multipole_spectrum_options());
  int n = 0;
  for (double cm : {0.002, 0.02, 0.1, 0.4})
    for (double bm : {0.1, 0.5, 0.9})
      for (double ch : {0.002, 0.02, 0.15}) {
        const auto truth = params(cm, bm, ch);
        const FitResult r = fitter.fit(synthetic(truth, fitter.options()));
        SCOPED_TRACE(::testing::Message() << truth << " -> " << r);
        EXPECT_LT(r.rms, 1e-5);
        EXPECT_NEAR(r.parameters.melanin, cm, 0.02 * cm);
        EXPECT_NEAR(r.parameters.melanin_blend, bm, 0.02);
        EXPECT_NEAR(r.parameters.hemoglobin, ch, (cm >= 0.3 ? 0.15 : 0.02) * ch);
        ++n;
      }
  EXPECT_EQ(n, 36);
}

// With noise sigma = 0.005 (typical spectrophotometer repeatability), the error of each
// parameter must be consistent with the reported one-sigma uncertainty: within 4 sigma always
// (a Gaussian exceeds that with probability 6e-5), and the reported sigma must be finite.
TEST(SpectrumFit, RoundTripNoisyWithinReportedUncertainty) {
  const SpectrumFitter fitter(skin_test::multipole_spectrum_options());
  unsigned seed = 11;
  int within2 = 0, total = 0;
  for (double cm : {0.005, 0.05, 0.2})
    for (double bm : {0.3, 0.7})
      for (double ch : {0.005, 0.05}) {
        const auto truth = params(cm, bm, ch);
        const FitResult r = fitter.fit(synthetic(truth, fitter.options(), 0.005, seed++));
        SCOPED_TRACE(::testing::Message() << truth << " -> " << r);
        EXPECT_NEAR(r.rms, 0.005, 0.0015);  // the residual is the noise
        for (std::size_t i = 0; i < r.free.size(); ++i) {
          if (r.at_bound[i]) continue;
          const double err = std::abs(get(r.parameters, r.free[i]) - get(truth, r.free[i]));
          ASSERT_TRUE(std::isfinite(r.uncertainty[i]));
          EXPECT_LT(err, 4.0 * r.uncertainty[i]) << key(r.free[i]);
          within2 += err < 2.0 * r.uncertainty[i];
          ++total;
        }
      }
  // 2 sigma holds for 95 % of Gaussian errors; allow for the linearisation: at least 80 %.
  EXPECT_GE(within2, 0.8 * total);
}

TEST(SpectrumFit, SpecularTermRecoversOiliness) {
  SpectrumFitOptions o = skin_test::multipole_spectrum_options();
  o.includes_specular = true;
  const SpectrumFitter fitter(o);
  auto truth = params(0.03, 0.6, 0.01);
  truth.oiliness = 0.6;
  const FitResult r = fitter.fit(synthetic(truth, fitter.options()));
  SCOPED_TRACE(::testing::Message() << r);
  EXPECT_NEAR(r.parameters.oiliness, 0.6, 0.01);
  // F at normal incidence for n = 1.4: ((1.4 - 1) / 2.4)^2 = 1/36.
  EXPECT_NEAR(r.specular, 0.6 / 36.0, 1e-3);
  EXPECT_LT(r.rms, 1e-5);
}

TEST(SpectrumFit, ExtendedTermsRoundTrip) {
  SpectrumFitOptions o = skin_test::multipole_spectrum_options();
  o.free = parse_parameter_list("melanin,melanin-blend,hemoglobin,oxygenation,scattering-scale,beta-carotene");
  const SpectrumFitter fitter(o);
  auto truth = params(0.02, 0.5, 0.02);
  truth.oxygenation = 0.55;
  truth.scattering_scale = 1.6;
  truth.beta_carotene = 20;
  const FitResult r = fitter.fit(synthetic(truth, fitter.options()));
  SCOPED_TRACE(::testing::Message() << r);
  EXPECT_LT(r.rms, 1e-4);
  EXPECT_NEAR(r.parameters.oxygenation, 0.55, 0.02);
  EXPECT_NEAR(r.parameters.scattering_scale, 1.6, 0.03);
  EXPECT_NEAR(r.parameters.beta_carotene, 20, 2);
}

TEST(SpectrumFit, BoundsAreRespected) {
  SpectrumFitOptions o = skin_test::multipole_spectrum_options();
  o.bounds = {{Parameter::melanin, {0.0, 0.01}}};
  const SpectrumFitter fitter(o);
  const FitResult r = fitter.fit(synthetic(params(0.05, 0.5, 0.01), fitter.options()));
  EXPECT_LE(r.parameters.melanin, 0.01);
  EXPECT_TRUE(r.at_bound[0]);
  EXPECT_GT(r.rms, 1e-3);  // the truth is outside: the fit cannot reproduce it
}

TEST(SpectrumFit, ArbitrarySamplingAndRange) {
  // 5 nm steps over 450-650 nm only (the minimum coverage): still recovered.
  const SpectrumFitter fitter(skin_test::multipole_spectrum_options());
  MeasuredSpectrum m;
  for (double l = 450; l <= 650; l += 5) m.wavelength_nm.push_back(l);
  const auto truth = params(0.05, 0.3, 0.03);
  m.R = model_reflectance(truth, m.wavelength_nm, fitter.options());
  const FitResult r = fitter.fit(m);
  EXPECT_NEAR(r.parameters.melanin, 0.05, 1e-3);
  EXPECT_NEAR(r.parameters.hemoglobin, 0.03, 1e-3);
  EXPECT_EQ(r.wavelength_nm.size(), m.wavelength_nm.size());
}

// Bad input: every problem is an InputError whose message names it.
namespace {
std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("skin_fit_test_" + name);
  std::ofstream(path) << text;
  return path.string();
}
std::string error_of(const std::string& path) {
  try {
    read_spectrum(path);
  } catch (const skin::util::InputError& e) {
    return e.what();
  }
  return "";
}
std::string csv(double from, double to, double step, double value) {
  std::string s = "lambda_nm,R\n";
  for (double l = from; l <= to; l += step) s += std::to_string(l) + "," + std::to_string(value) + "\n";
  return s;
}
}  // namespace

TEST(SpectrumInput, Malformed) {
  EXPECT_NE(error_of(write_temp("bad1.csv", "lambda_nm,R\n400,0.1\n410,abc\n")), "");
  EXPECT_NE(error_of(write_temp("bad2.csv", "lambda_nm,R\n400,0.1,3\n")), "");
  EXPECT_NE(error_of("/nonexistent/spectrum.csv"), "");
}
TEST(SpectrumInput, TooFewSamples) {
  EXPECT_NE(error_of(write_temp("few.csv", csv(400, 700, 100, 0.3))).find("at least"), std::string::npos);
}
TEST(SpectrumInput, OutOfRangeReflectance) {
  EXPECT_NE(error_of(write_temp("pct.csv", csv(400, 700, 10, 35))).find("percentage"), std::string::npos);
  EXPECT_NE(error_of(write_temp("neg.csv", csv(400, 700, 10, -0.1))).find("reflectance"), std::string::npos);
}
TEST(SpectrumInput, RangeMustCover450To650) {
  EXPECT_NE(error_of(write_temp("short.csv", csv(500, 700, 5, 0.3))).find("450-650"), std::string::npos);
}
TEST(SpectrumInput, WavelengthsMustIncrease) {
  EXPECT_NE(error_of(write_temp("order.csv", "lambda_nm,R\n400,0.1\n390,0.1\n")).find("increase"), std::string::npos);
}
TEST(SpectrumInput, OiilinessNeedsTheSpecularTerm) {
  SpectrumFitOptions o = skin_test::multipole_spectrum_options();
  o.free = {Parameter::melanin, Parameter::oiliness};
  EXPECT_THROW(SpectrumFitter{o}, skin::util::InputError);
  EXPECT_THROW(parse_parameter_list("melanin,melanin"), skin::util::InputError);
  EXPECT_THROW(parse_parameter("carotene"), skin::util::InputError);
  EXPECT_EQ(parse_parameter("scattering-scale"), Parameter::scattering_scale);
  EXPECT_EQ(parse_parameter("beta_carotene"), Parameter::beta_carotene);
}

// The fit's parameters are the parameter table's rows with a fit interval: their names, member
// and bounds come from the table, the paper's symbols are accepted wherever keys are, and a
// parameter named twice (by key and by symbol) is refused.
TEST(FitParameters, ComeFromTheParameterTable) {
  std::size_t fittable = 0;
  for (const skin::physics::ParameterInfo& row : skin::physics::parameter_table()) {
    if (!row.fittable()) {
      EXPECT_THROW(parse_parameter(row.key), skin::util::InputError) << row.key;
      continue;
    }
    ++fittable;
    const Parameter p = parse_parameter(row.key);
    EXPECT_EQ(&p.info(), &row);
    EXPECT_EQ(parse_parameter(row.flag()), p);
    if (!row.symbol.empty()) {
      EXPECT_EQ(parse_parameter(row.symbol), p) << row.symbol;
    }
    EXPECT_EQ(key(p), row.key);
    EXPECT_EQ(flag(p), row.flag());
    // The fit interval lies inside the parameter's range.
    const Bounds b = default_bounds(p);
    EXPECT_LT(b.lo, b.hi) << row.key;
    EXPECT_TRUE(row.in_range(b.lo) && row.in_range(b.hi)) << row.key;
    skin::physics::SkinParameters s;
    set(s, p, 0.125);
    EXPECT_EQ(s.*(row.member), 0.125);
    EXPECT_EQ(get(s, p), 0.125);
  }
  EXPECT_EQ(all_parameters().size(), fittable);
  for (Parameter p : {Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin, Parameter::oiliness,
                      Parameter::oxygenation, Parameter::epidermis_thickness, Parameter::epidermal_hemoglobin,
                      Parameter::beta_carotene, Parameter::bilirubin, Parameter::scattering_scale})
    EXPECT_NE(std::find(all_parameters().begin(), all_parameters().end(), p), all_parameters().end()) << key(p);
  // The intervals the fit has always used (its results depend on them).
  EXPECT_EQ(default_bounds(Parameter::melanin).hi, 0.5);
  EXPECT_EQ(default_bounds(Parameter::hemoglobin).hi, 0.2);
  EXPECT_EQ(default_bounds(Parameter::epidermis_thickness).lo, 0.02);
  EXPECT_EQ(default_bounds(Parameter::scattering_scale).lo, 0.25);
  EXPECT_EQ(default_bounds(Parameter::scattering_scale).hi, 4.0);

  EXPECT_EQ(parse_parameter_list("C_m, beta_m,C_h,gamma"),
            (std::vector<Parameter>{Parameter::melanin, Parameter::melanin_blend, Parameter::hemoglobin,
                                    Parameter::oxygenation}));
  EXPECT_THROW(parse_parameter_list("melanin,C_m"), skin::util::InputError);
  EXPECT_THROW(parse_parameter("eta"), skin::util::InputError);  // in the table, not fitted
  SpectrumFitOptions o = skin_test::multipole_spectrum_options();
  o.bounds = {{parse_parameter("melanin"), {0.0, 0.1}}, {parse_parameter("C_m"), {0.0, 0.2}}};
  EXPECT_THROW(SpectrumFitter{o}, skin::util::InputError);
}

// The multipole's real source must lie inside the epidermis (z_r = 1 / sigma_t' < d): outside
// it the model is undefined for the fit (NaN), which keeps the search out of the region where
// the slab transmittance changes sign.
TEST(SpectrumFit, MultipoleDomainBarrier) {
  const auto model = skin_test::multipole();
  auto p = params(0.01, 0.5, 0.01);
  EXPECT_TRUE(std::isfinite(model(p, 650)));
  p.epidermis_thickness = 0.1;  // sigma_t' at 650 nm is ~5/mm: z_r = 0.2 mm > d
  EXPECT_TRUE(std::isnan(model(p, 650)));
}

// DJ06 Fig. 9 compares the model with four measured spectra (Vrhel et al. 1994: 82, 95, 110,
// 117). The extended model must fit each to RMS < 0.02 over 400-700 nm (the target).
TEST(MeasuredSpectra, PaperSpectraFitWithExtendedModel) {
  const std::string path = std::string(SKIN_SHARED_DATA_DIR) + "/skin_spectra/vrhel_ncsu/vrhel_skin_reflectance.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "measured spectra not available: " << path;
  SpectrumFitOptions paper = skin_test::multipole_spectrum_options(), ext = paper;
  ext.includes_specular = true;
  for (Parameter p : extended_parameters()) ext.free.push_back(p);
  const SpectrumFitter f_paper(paper), f_ext(ext);
  for (const std::string col : {"vrhel_082", "vrhel_095", "vrhel_110", "vrhel_117"}) {
    const MeasuredSpectrum m = read_spectrum(path, col);
    const FitResult a = f_paper.fit(m), b = f_ext.fit(m);
    SCOPED_TRACE(::testing::Message() << col << " paper " << a << " extended " << b);
    EXPECT_LT(b.rms, 0.02);
    EXPECT_LE(b.rms, a.rms + 1e-9);  // a superset of parameters can only do better
    EXPECT_LT(a.rms, 0.05);          // the paper's model is already in the right region
  }
}

// Vessel packaging against independent measurements: three light Vrhel spectra (ITA 43-51, the
// light bin of docs/fit.md), fitted with the extended model (accurate solver, priors) with and
// without the vessel radius free. Measured 2026-12-07: RMS 0.0069 -> 0.0054 (vrhel_089),
// 0.0075 -> 0.0048 (vrhel_096), 0.0142 -> 0.0120 (vrhel_081), radius 0.024-0.030 mm; asserted:
// at least 10 % lower each (measured 16-36 %), the radius inside its interval, off its lower end.
// (The first only under the sanitizers: 47 s for three there.)
TEST(MeasuredSpectra, VesselPackagingLowersTheResidualOfLightSkin) {
  const std::string path = std::string(SKIN_SHARED_DATA_DIR) + "/skin_spectra/vrhel_ncsu/vrhel_skin_reflectance.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "measured spectra not available: " << path;
  SpectrumFitOptions with;
  use_fit_model(with, FitModel::extended);
  SpectrumFitOptions without = with;
  std::erase(without.free, Parameter::blood_vessel_radius);
  ASSERT_EQ(without.free.size() + 1, with.free.size());
  const SpectrumFitter f_with(with), f_without(without);
  for (const std::string& col : skin::test::sanitized<std::string>({"vrhel_089", "vrhel_096", "vrhel_081"})) {
    const MeasuredSpectrum m = read_spectrum(path, col);
    const FitResult a = f_without.fit(m), b = f_with.fit(m);
    SCOPED_TRACE(::testing::Message() << col << " without " << a.rms << " with " << b.rms << " radius "
                                      << b.parameters.blood_vessel_radius);
    EXPECT_LT(b.rms, 0.9 * a.rms);
    EXPECT_GT(b.parameters.blood_vessel_radius, 0.005);
    EXPECT_LE(b.parameters.blood_vessel_radius, 0.05);
    EXPECT_EQ(a.parameters.blood_vessel_radius, 0.0);
  }
}

// An independent set: the NIST reference spectra (Cooksey, Allen & Tsai 2017; 100 subjects, inner
// forearm, integrating sphere with the surface reflection; data/skin_spectra/nist_2017), one
// subject per skin-tone bin with spectra there (ITA 63, 52, 31, 14, -22), fitted with
// `--model extended` and the surface term. Measured 2026-12-07 (accurate solver): RMS 0.0062,
// 0.0051, 0.0030, 0.0023, 0.0021 (over all 100: median 0.0043, worst 0.0065), the paper model's
// 0.044, 0.034, 0.031, 0.014, 0.0095; asserted: below 0.0075 each and under half the paper
// model's (measured 4.5-7x under it). 4 s for the five in Release.
TEST(MeasuredSpectra, IndependentNistSetFitsTheExtendedModel) {
  const std::string path = std::string(SKIN_SOURCE_DIR) + "/data/skin_spectra/nist_2017/nist_skin_reflectance.csv";
  SpectrumFitOptions ext, paper;
  use_fit_model(ext, FitModel::extended);
  ext.includes_specular = true;
  const SpectrumFitter f_ext(ext), f_paper(paper);
  for (const std::string& col :
       skin::test::sanitized<std::string>({"nist_041", "nist_014", "nist_001", "nist_039", "nist_044"})) {
    const MeasuredSpectrum m = read_spectrum(path, col);
    ASSERT_EQ(m.wavelength_nm.front(), 379.0);
    ASSERT_EQ(m.wavelength_nm.back(), 781.0);
    const FitResult a = f_paper.fit(m), b = f_ext.fit(m);
    SCOPED_TRACE(::testing::Message() << col << " paper " << a.rms << " extended " << b);
    EXPECT_LT(b.rms, 0.0075);
    EXPECT_LT(2 * b.rms, a.rms);
  }
}

// A measurement through a 5 mm port (pencil beam at its centre) of known skin, made with the
// accurate model's profiles: fitted with the port, the three parameters come back (measured: RMS
// 8e-12, each to 1e-10); fitted as if all of R_d were collected, the red light lost beyond the
// port's edge is read as skin (measured: RMS 0.0046, blood 0.0085 instead of 0.02, beta_m on its
// bound 1). Asserted: the first to 1e-4 RMS and 2 %, the second at least 30 % low in blood.
TEST(SpectrumFit, ThroughAPortKnownAnswer) {
  const auto truth = params(0.02, 0.6, 0.02);
  const ForwardModel port = forward_model_through_port(skin::transport::default_model(), 2.5);
  MeasuredSpectrum m{"through a port", {}, {}};
  for (double l = 400; l <= 700; l += 10) {
    m.wavelength_nm.push_back(l);
    m.R.push_back(port(truth, l));
  }
  SpectrumFitOptions with, without;
  with.model = port;
  const FitResult a = SpectrumFitter(with).fit(m), b = SpectrumFitter(without).fit(m);
  SCOPED_TRACE(::testing::Message() << "with the port " << a << "; without " << b);
  EXPECT_LT(a.rms, 1e-4);
  EXPECT_NEAR(a.parameters.melanin, 0.02, 0.02 * 0.02);
  EXPECT_NEAR(a.parameters.melanin_blend, 0.6, 0.02);
  EXPECT_NEAR(a.parameters.hemoglobin, 0.02, 0.02 * 0.02);
  EXPECT_GT(b.rms, 10 * a.rms);
  EXPECT_LT(b.parameters.hemoglobin, 0.7 * 0.02);
  // Radii out of range are refused when the model is made, naming the parameter.
  EXPECT_THROW(forward_model_through_port(skin::transport::default_model(), -1), skin::util::InputError);
  EXPECT_THROW(forward_model_through_port(skin::transport::default_model(), 2.5, 3), skin::util::InputError);
}

// The fits of a directory with one synthetic spectrum (known parameters) and its metadata
// (skin::fit), and their report (src/app): markdown names it, flags it, and the plot exists.
TEST(MeasuredReport, WritesMarkdownAndPlots) {
  namespace fs = std::filesystem;
  const skin::test::TempDir tmp("skin_fit_report");
  const fs::path dir = tmp.path() / "in", out = tmp.path() / "out";
  fs::create_directories(dir);
  const auto truth = params(0.05, 0.5, 0.02);
  std::vector<double> l;
  for (double x = 400; x <= 700; x += 10) l.push_back(x);
  const auto R = model_reflectance(truth, l, skin_test::multipole_spectrum_options());
  {
    // synth_b: the same skin measured with its surface reflection (rho_s F, rho_s 0.5, F 0.028),
    // flagged includes_specular in the metadata.
    std::ofstream f(dir / "spectra.csv");
    f << "lambda_nm,synth_a,synth_b\n";
    for (std::size_t i = 0; i < l.size(); ++i) f << l[i] << "," << R[i] << "," << 0.014 + (1 - 0.014) * R[i] << "\n";
    std::ofstream(dir / "spectra_metadata.csv") << "Column,original_label,used_in_donner_jensen_2006,includes_specular\n"
                                                   "synth_a,\"synthetic, known answer\",yes,no\n"
                                                   "synth_b,with its surface reflection,no,Yes\n";
  }
  const auto entries = fit_measured_spectra(dir.string(), skin_test::multipole());
  std::ostringstream md;
  skin::cli::write_measured_report(md, entries, dir.string(), out.string(), "multipole");
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_FALSE(entries[0].includes_specular);
  EXPECT_TRUE(entries[1].includes_specular);
  EXPECT_FALSE(entries[1].used_in_paper);
  // Only the flagged spectrum's extended-model fit has the surface term (oiliness free).
  auto frees_oiliness = [](const skin::fit::FitResult& r) {
    return std::find(r.free.begin(), r.free.end(), skin::fit::Parameter::oiliness) != r.free.end();
  };
  EXPECT_FALSE(frees_oiliness(entries[0].extended_model));
  EXPECT_TRUE(frees_oiliness(entries[1].extended_model));
  EXPECT_NE(md.str().find("1 of the 2 spectra are flagged"), std::string::npos);
  EXPECT_NE(md.str().find("with none on an end of its range:"), std::string::npos);
  EXPECT_TRUE(entries[0].used_in_paper);
  EXPECT_EQ(entries[0].description, "synthetic, known answer");
  EXPECT_LT(entries[0].paper.rms, 1e-4);
  EXPECT_LE(entries[0].extended.rms, entries[0].paper.rms + 1e-9);
  EXPECT_NE(md.str().find("synth_a*"), std::string::npos);
  EXPECT_NE(md.str().find("with the multipole R_d"), std::string::npos);
  // The good-fit limit (fit::kGoodFitRms, which the web page warns at) as the report writes it.
  EXPECT_NE(md.str().find("| model | median RMS | worst RMS | RMS < 0.02 |"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "synth_a.png"));
  // Without plots: no spectrum's PNG is written or linked.
  std::ostringstream md_text;
  skin::cli::write_measured_report(md_text, entries, dir.string(), (tmp.path() / "text").string(), "multipole", false);
  EXPECT_EQ(md_text.str().find("synth_a.png"), std::string::npos);
  EXPECT_EQ(md_text.str().find("synth_b.png"), std::string::npos);
  EXPECT_NE(md_text.str().find("| synth_a* |"), std::string::npos);
  EXPECT_FALSE(fs::exists(tmp.path() / "text" / "synth_a.png"));
  // The one figure of the set (the median fit of each skin-tone bin) is drawn either way.
  EXPECT_TRUE(fs::exists(out / "tone_bins.png"));
  EXPECT_TRUE(fs::exists(tmp.path() / "text" / "tone_bins.png"));
  EXPECT_NE(md_text.str().find("](tone_bins.png)"), std::string::npos);
  EXPECT_THROW(fit_measured_spectra((dir / "missing").string()), skin::util::InputError);
  EXPECT_THROW(fit_measured_spectra(out.string()), skin::util::InputError);  // a directory, no *.csv
}

// Forward models by name; a spectrum made with the adding-doubling solver is recovered by a fit
// that uses it (the fit does not depend on the multipole).
TEST(SpectrumFit, SolversByName) {
  EXPECT_THROW(forward_model("diffusion-ish"), skin::util::InputError);
  EXPECT_NO_THROW(forward_model("multipole"));
  SpectrumFitOptions o;
  o.model = forward_model("accurate");
  const SpectrumFitter fitter(o);
  MeasuredSpectrum m;
  for (double l = 400; l <= 700; l += 10) m.wavelength_nm.push_back(l);
  const auto truth = params(0.04, 0.5, 0.02);
  m.R = model_reflectance(truth, m.wavelength_nm, o);
  const FitResult r = fitter.fit(m);
  SCOPED_TRACE(::testing::Message() << r);
  EXPECT_LT(r.rms, 1e-5);
  EXPECT_NEAR(r.parameters.melanin, 0.04, 0.02 * 0.04);
  EXPECT_NEAR(r.parameters.hemoglobin, 0.02, 0.02 * 0.02);
}
