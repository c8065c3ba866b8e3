"""The Python bindings give the same numbers as the C++ model, with the same names."""
import json
import math
import os
import subprocess
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

    def test_the_readme_example_runs(self):
        readme = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "README.md")
        with open(readme, encoding="utf-8") as f:
            text = f.read()
        section = text[text.index("### Python"):]
        start = section.index("```python\n") + len("```python\n")
        block = section[start:section.index("```\n", start)]
        self.assertIn("import spectral_skin", block)
        exec(compile(block, "README.md (### Python)", "exec"), {})

    def test_bad_input_raises_value_error_naming_the_parameter(self):
        with self.assertRaisesRegex(ValueError, r"melanin \(C_m\) = 1.5 is out of range"):
            ss.spectrum(melanin=1.5)
        self.assertIn("ear", ss.presets())


def value_in_range(p):
    """A value inside p's range, away from its default (and from the presets' values)."""
    if p["max"] is None:
        return p["default"] * 1.37
    return p["min"] + 0.37 * (p["max"] - p["min"])


class ParameterKeywords(unittest.TestCase):
    """The keywords are the parameter table's keys and symbols, as the CLI's flags are."""

    def spectrum(self, **kw):
        # Seven wavelengths and the multipole model: the keywords are under test, not the solver.
        return ss.spectrum("african", lambda_step=50, solver="multipole", **kw)

    def test_parameters_match_the_cli(self):
        binary = os.environ.get("SKIN_BINARY")
        if not binary:
            self.skipTest("SKIN_BINARY (the skin command) not set; CTest sets it")
        cli = json.loads(subprocess.run([binary, "parameters", "--format", "json"], check=True,
                                        capture_output=True, text=True).stdout)
        self.assertEqual(ss.parameters(), cli)

    def test_table_shape(self):
        table = ss.parameters()
        self.assertEqual([p["key"] for p in table][:4],
                         ["melanin", "melanin_blend", "hemoglobin", "oiliness"])
        self.assertEqual({p["symbol"] for p in table if p["symbol"]},
                         {"C_m", "beta_m", "C_h", "rho_s", "gamma"})
        g = next(p for p in table if p["key"] == "g")
        self.assertEqual((g["min"], g["max"], g["min_exclusive"], g["default"]), (-1, 1, True, 0.9))
        thickness = next(p for p in table if p["key"] == "epidermis_thickness")
        self.assertIsNone(thickness["max"])
        self.assertEqual(thickness["flag"], "--epidermis-thickness")
        self.assertEqual(ss.solvers(), ["accurate", "multipole"])

    def test_every_key_is_a_keyword(self):
        preset = self.spectrum()["parameters"]
        self.assertEqual(set(preset), {p["key"] for p in ss.parameters()})
        for p in ss.parameters():
            with self.subTest(key=p["key"]):
                v = value_in_range(p)
                self.assertNotEqual(v, preset[p["key"]])
                got = self.spectrum(**{p["key"]: v})["parameters"]
                self.assertEqual(got, dict(preset, **{p["key"]: v}))

    def test_symbols_are_aliases(self):
        for p in ss.parameters():
            if p["symbol"] is None:
                continue
            with self.subTest(symbol=p["symbol"]):
                v = value_in_range(p)
                by_symbol = self.spectrum(**{p["symbol"]: v})
                by_key = self.spectrum(**{p["key"]: v})
                self.assertEqual(by_symbol["parameters"][p["key"]], v)
                self.assertEqual(by_symbol, by_key)
        with self.assertRaisesRegex(ValueError,
                                    "^melanin is given twice: melanin and C_m name the same"):
            self.spectrum(melanin=0.1, C_m=0.2)

    def test_keywords_change_the_physics(self):
        # Not only the echo: more melanin darkens the spectrum at every wavelength.
        base = ss.spectrum("caucasian", lambda_step=50, solver="multipole")
        dark = ss.spectrum("caucasian", lambda_step=50, solver="multipole", C_m=0.4)
        self.assertTrue(all(d < b for d, b in zip(dark["R_d"], base["R_d"])))
        profile = ss.rgb_profile("african", r_mm=[0.5], solver="multipole", C_h=0.2)
        self.assertEqual(profile["parameters"]["hemoglobin"], 0.2)

    def test_none_keeps_the_preset(self):
        self.assertEqual(self.spectrum(melanin=None, g=None, C_h=None), self.spectrum())

    def test_booleans_and_text_are_not_numbers(self):
        with self.assertRaisesRegex(ValueError, "^melanin must be a number, not True$"):
            self.spectrum(melanin=True)
        with self.assertRaisesRegex(ValueError, "^hemoglobin must be a number, not False$"):
            self.spectrum(C_h=False)
        with self.assertRaisesRegex(ValueError, "^eta must be a number, not '1.4'$"):
            self.spectrum(eta="1.4")
        self.assertEqual(self.spectrum(eta=2)["parameters"]["eta"], 2.0)  # an int is a number

    def test_unknown_keyword_lists_the_known_keys(self):
        with self.assertRaises(ValueError) as e:
            self.spectrum(melanine=0.1)
        message = str(e.exception)
        self.assertTrue(message.startswith("parameter 'melanine' is unknown: known parameters are "))
        for p in ss.parameters():
            self.assertIn(p["key"], message)


if __name__ == "__main__":
    unittest.main()
