"""The Python bindings give the same numbers as the C++ model, with the same names."""
import math
import unittest

import spectral_skin as ss


class Bindings(unittest.TestCase):
    def test_semi_infinite_layer_is_the_classic_dipole(self):
        # alpha' = 1 / 1.01, A(1.4) = 3.2507: Jensen et al. 2001 closed form.
        a = 1 / 1.01
        A = 3.250697461379377
        root = math.sqrt(3 * (1 - a))
        expected = a / 2 * (1 + math.exp(-4 / 3 * A * root)) * math.exp(-root)
        r = ss.layers([{"sigma_a": 0.01, "sigma_s_prime": 1.0}], solver="multipole")
        self.assertAlmostEqual(r["R_d"], expected, places=12)
        self.assertEqual(r["T_d"], 0.0)

    def test_spectrum_keywords_and_solvers(self):
        s = ss.spectrum("african", lambda_step=10, melanin=0.4)
        self.assertEqual(len(s["R_d"]), 31)
        self.assertEqual(s["solver"], "accurate")
        m = ss.spectrum("african", lambda_step=10, melanin=0.4, solver="multipole")
        self.assertGreater(m["R_d"][5], s["R_d"][5])  # diffusion overstates dark skin at 450 nm
        self.assertEqual(len(s["color"]["hex"]), 7)

    def test_profile_integrates_to_total(self):
        n = 600
        r = [1e-4 * (60 / 1e-4) ** (i / (n - 1)) for i in range(n)]
        p = ss.rgb_profile("caucasian", r_mm=r)
        for c in "rgb":
            R = p["R"][c]
            total = math.pi * r[0] ** 2 * R[0] + sum(
                math.pi * (R[i] * r[i] + R[i + 1] * r[i + 1]) * (r[i + 1] - r[i]) for i in range(n - 1))
            self.assertAlmostEqual(total / p["R_d"]["rgb".index(c)], 1.0, delta=0.005)

    def test_validity_outside_the_accurate_tables(self):
        # A dark top layer (alpha' = 0.038, below the transport tables' 0.0975) over a bright
        # half-space: the profile is flagged (with a RuntimeWarning), R_d stays exact.
        layers = [{"sigma_a": 50.0, "sigma_s_prime": 2.0, "thickness": 0.05},
                  {"sigma_a": 0.001, "sigma_s_prime": 10.0}]
        with self.assertWarnsRegex(RuntimeWarning, "solver accurate: profile outside"):
            r = ss.layers(layers, r_mm=[0.3, 3.0])
        self.assertEqual(r["validity"]["profile"], False)
        self.assertEqual(r["validity"]["totals"], True)
        with self.assertWarnsRegex(RuntimeWarning, "g = 0.7"):
            p = ss.rgb_profile("caucasian", r_mm=[0.3, 3.0], g=0.7)
        self.assertEqual(p["validity"]["profile"], False)
        self.assertEqual(ss.rgb_profile("caucasian", r_mm=[0.3])["validity"]["profile"], True)

    def test_bad_input_raises_value_error_naming_the_parameter(self):
        with self.assertRaisesRegex(ValueError, r"melanin \(C_m\) = 1.5 is out of range"):
            ss.spectrum(melanin=1.5)
        with self.assertRaisesRegex(ValueError, "unknown parameter 'melanine'"):
            ss.spectrum(melanine=0.1)
        self.assertIn("ear", ss.presets())


if __name__ == "__main__":
    unittest.main()
