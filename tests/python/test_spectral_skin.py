"""The Python package gives the `skin` command's numbers (to 1e-12), with the same names, as numpy
arrays with named axes, for one parameter set or arrays of them."""
import json
import math
import warnings
import os
import subprocess
import tempfile
import time
import unittest

import numpy as np

import spectral_skin as ss

SKIN = os.environ.get("SKIN_BINARY")
SOURCE_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def cli(*args):
    """The JSON document of `skin ARGS --format json`."""
    out = subprocess.run([SKIN, *args, "--format", "json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def assert_same(test, py, js, path="", rtol=1e-12):
    """Every key of the CLI's JSON `js` is in `py` with the same value (numbers to rtol)."""
    if isinstance(js, dict):
        for k, v in js.items():
            test.assertIn(k, py, path)
            assert_same(test, py[k], v, f"{path}.{k}", rtol)
    elif isinstance(js, list) and any(isinstance(x, dict) for x in js):
        test.assertEqual(len(py), len(js), path)
        for i, (p, j) in enumerate(zip(py, js)):
            assert_same(test, p, j, f"{path}[{i}]", rtol)
    elif isinstance(js, list) and all(isinstance(x, str) for x in js):
        test.assertEqual(list(py), js, path)
    elif isinstance(js, list) or isinstance(py, np.ndarray):
        a = np.asarray(py)
        b = np.asarray(js, dtype=a.dtype if a.dtype.kind in "iub" else float)
        test.assertEqual(a.shape, b.shape, path)
        if a.dtype.kind in "fi":
            np.testing.assert_allclose(a, b, rtol=rtol, atol=0, err_msg=path)
        else:
            np.testing.assert_array_equal(a, b, err_msg=path)
    elif isinstance(js, float) and not isinstance(py, (bool, str)):
        test.assertTrue(math.isclose(py, js, rel_tol=rtol, abs_tol=0), f"{path}: {py} != {js}")
    else:
        test.assertEqual(py, js, path)


def assert_equal(test, a, b):
    np.testing.assert_equal(a, b)


@unittest.skipUnless(SKIN, "SKIN_BINARY (the skin command) not set; CTest sets it")
class SameAsTheCommand(unittest.TestCase):
    """Each function equals its subcommand's JSON to 1e-12 (the same library code runs; the
    tolerance allows only for the JSON's decimal round trip)."""

    def test_batch_profiles_that_are_solved_say_so_and_count_wavelengths_on_a_terminal(self):
        # `skin batch --radius` of skin whose wavelengths are solved (sfd: ~1 s each): on a
        # terminal a note with the estimate before the work, then a bar of wavelengths; piped,
        # nothing on stderr; the same CSV either way.
        import pty
        args = [SKIN, "batch", "--solver", "sfd", "--sweep", "melanin=0.1:0.2:2", "--lambda-min", "600",
                "--lambda-max", "600", "--lambda-step", "20", "--radius", "0.1"]
        with tempfile.TemporaryDirectory() as d:
            on_terminal, piped = os.path.join(d, "t.csv"), os.path.join(d, "p.csv")
            master, slave = pty.openpty()
            proc = subprocess.Popen(args + ["-o", on_terminal], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                    stderr=slave, close_fds=True)
            os.close(slave)
            chunks = []
            while True:
                try:
                    data = os.read(master, 65536)
                except OSError:  # EIO: the writer closed the terminal
                    break
                if not data:
                    break
                chunks.append(data)
            os.close(master)
            self.assertEqual(proc.wait(timeout=120), 0)
            err = b"".join(chunks).decode("utf-8", "replace")
            self.assertIn("skin: note: 2 of 2 wavelength profiles are off the skin and half-space tables and solved "
                          "in the frequency domain: about ", err)
            self.assertIn("2/2 wavelengths", err)
            quiet = subprocess.run(args + ["-o", piped], check=True, capture_output=True, text=True)
            self.assertEqual(quiet.stderr, "")
            with open(on_terminal, encoding="utf-8") as a, open(piped, encoding="utf-8") as b:
                self.assertEqual(a.read(), b.read())

    def test_export(self):
        # The same files and fit report as `skin export` (the report's "files" lists paths only
        # the command writes).
        with tempfile.TemporaryDirectory() as d:
            main = os.path.join(d, "skin.mtlx")
            subprocess.run([SKIN, "export", "--target", "openpbr", "--preset", "african", "--melanin",
                            "0.3", "--name", "skin", "-o", main], check=True, capture_output=True)
            py = ss.export("openpbr", "african", melanin=0.3, name="skin")
            with open(main, encoding="utf-8") as f:
                self.assertEqual(py["files"][""], f.read())
            with open(os.path.join(d, "skin.fit.json"), encoding="utf-8") as f:
                js = json.load(f)
            del js["files"]
            assert_same(self, py["report"], js)
            # The report converted from the document: arrays of numbers as numpy arrays.
            self.assertIsInstance(py["report"]["values"]["subsurface_color"], np.ndarray)
            self.assertEqual(py["report"]["values"]["subsurface_color"].dtype, np.float64)
            self.assertEqual(py["report"]["notes"], [])
        with self.assertRaises(ValueError):
            ss.export("renderman")

    def test_spectrum(self):
        for solver in ss.solvers():
            with self.subTest(solver=solver):
                py = ss.spectrum("african", lambda_step=10, melanin=0.3, C_h=0.02, solver=solver)
                js = cli("spectrum", "--preset", "african", "--lambda-step", "10", "--melanin", "0.3",
                         "--C_h", "0.02", "--solver", solver)
                assert_same(self, py, js)  # every key of the command's document, units too

    def test_color(self):
        py = ss.color("tanned", melanin=0.05)
        js = cli("color", "--preset", "tanned", "--melanin", "0.05")
        assert_same(self, py, js)
        py = ss.color("tanned", illuminant="LED-B3", melanin=0.05)
        js = cli("color", "--preset", "tanned", "--illuminant", "LED-B3", "--melanin", "0.05")
        self.assertEqual(py["illuminant"], "LED-B3")
        assert_same(self, py, js)
        self.assertEqual(ss.illuminants()[:3], ["D65", "D50", "A"])
        with self.assertRaisesRegex(ValueError, "illuminant = 'F3' is unknown: must be one of D65"):
            ss.color(illuminant="F3")
        # The names before CIE 015:2018 find their FL successors.
        self.assertEqual(ss.color(illuminant="F2")["illuminant"], "FL2")

    def test_profiles(self):
        r = np.geomspace(0.01, 8, 12)
        args = ["--radius-min", "0.01", "--radius-max", "8", "--samples", "12", "--lambda-step", "25"]
        js = cli("profile", "--rgb", "--preset", "asian", *args)
        py = ss.rgb_profile("asian", r_mm=js["r_mm"], lambda_step=25)
        np.testing.assert_allclose(js["r_mm"], r, rtol=1e-12)
        for c, name in enumerate(py["channel"]):
            np.testing.assert_allclose(py["R"][c], js["R"][name], rtol=1e-12, atol=0)
            np.testing.assert_allclose(py["R_d"][c], js["R_d"][name], rtol=1e-12, atol=0)
        assert_same(self, py["parameters"], js["parameters"])
        js = cli("profile", "--preset", "asian", "--solver", "multipole", *args)
        py = ss.profile("asian", r_mm=js["r_mm"], lambda_step=25, solver="multipole")
        assert_same(self, py, js)

    def test_layers(self):
        js = cli("layers", "--layer", "sigma_a=0.5,sigma_s_prime=5,thickness_mm=0.25",
                 "--layer", "sigma_a=0.05,sigma_s_prime=2.5", "--radius", "0.1", "--radius", "1")
        py = ss.layers([{"sigma_a": 0.5, "sigma_s_prime": 5, "thickness_mm": 0.25},
                        {"sigma_a": 0.05, "sigma_s_prime": 2.5, "thickness_mm": None}], r_mm=[0.1, 1])
        assert_same(self, py, js)  # the layers with their diffusion quantities too
        self.assertEqual(py["validity"]["reason"], "")  # the command leaves out an empty reason
        none = ss.layers([{"sigma_a": 0.01, "sigma_s_prime": 1.0}], solver="multipole")["profile"]
        self.assertEqual((none["r_mm"].dtype, none["R"].shape), (np.float64, (0,)))

    def test_mc(self):
        js = cli("mc", "--preset", "pale", "--wavelength", "650", "--photons", "3000", "--bins", "20",
                 "--threads", "2")
        py = ss.mc(preset="pale", wavelength=650, photons=3000, bins=20, threads=1)
        del js["seconds"]
        assert_same(self, py, js)

    def test_fit_spectrum(self):
        truth = ss.spectrum(melanin=0.03, melanin_blend=0.4, hemoglobin=0.02, lambda_step=10, solver="multipole")
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "measured.csv")
            with open(path, "w") as f:
                f.write("wavelength_nm,R\n")
                for w, r in zip(truth["wavelength_nm"], truth["R_d"]):
                    f.write(f"{w!r},{r!r}\n")
            js = cli("fit", "--spectrum", path, "--solver", "multipole")
        py = ss.fit_spectrum(truth["wavelength_nm"], truth["R_d"], solver="multipole")
        self.assertEqual(py["input"], "spectrum")  # the command's: the file's name
        del js["input"]
        assert_same(self, py, js, rtol=1e-9)  # the CSV's decimal digits
        self.assertAlmostEqual(py["parameters"]["melanin"], 0.03, places=6)

    def test_fit_spectrum_through_a_port(self):
        # A NIST subject (a sphere measurement of a ~5 mm area): the port's fit is the command's,
        # two spectra at once are two single fits, and bad radii are a ValueError naming them.
        path = os.path.join(SOURCE_DIR, "data", "skin_spectra", "nist_2017", "nist_skin_reflectance.csv")
        with open(path) as f:
            rows = [line.split(",") for line in f if not line.startswith("#")]
        data = np.array([[float(x) for x in r] for r in rows[1:]])
        wl, R = data[:, 0], data[:, [1, 44]].T
        with tempfile.TemporaryDirectory() as d:
            one = os.path.join(d, "nist_001.csv")
            with open(one, "w") as f:
                f.write("wavelength_nm,R\n")
                for w, r in zip(wl, R[0]):
                    f.write(f"{w!r},{r!r}\n")
            js = cli("fit", "--spectrum", one, "--port-radius", "2.5", "--beam-radius", "0.5")
        py = ss.fit_spectrum(wl, R[0], port_radius=2.5, beam_radius=0.5)
        self.assertEqual((py["port_radius"], py["beam_radius"]), (2.5, 0.5))
        del js["input"]
        assert_same(self, py, js, rtol=1e-9)
        plain = ss.fit_spectrum(wl, R[0])
        self.assertIsNone(plain["port_radius"])
        self.assertGreater(py["parameters"]["hemoglobin"], plain["parameters"]["hemoglobin"])
        many = ss.fit_spectrum(wl, R, port_radius=2.5, beam_radius=0.5)
        self.assertEqual(many["port_radius"], 2.5)
        for i in range(2):
            assert_row_is_the_single_call(self, many, ss.fit_spectrum(wl, R[i], port_radius=2.5, beam_radius=0.5), i)
        for kw, name in (({"port_radius": 0.0}, "port-radius"), ({"port_radius": 2.5, "beam_radius": 3.0}, "beam-radius"),
                         ({"beam_radius": 1.0}, "beam_radius")):
            with self.assertRaisesRegex(ValueError, name):
                ss.fit_spectrum(wl, R[0], **kw)

    def test_fit_color(self):
        js = cli("fit", "--hex", "a98f74", "--solver", "multipole")
        py = ss.fit_color(hex="a98f74", solver="multipole")
        assert_same(self, py, js)
        self.assertEqual(ss.fit_color(srgb="169,143,116", solver="multipole"), py)

    def test_fit_color_with_the_extended_model(self):
        # model= is the command's --model: the same fit, free set, gamut distance and bounds.
        js = cli("fit", "--hex", "c4a090", "--model", "extended")
        py = ss.fit_color(hex="c4a090", model="extended")
        assert_same(self, py, js)
        self.assertEqual(py["model"], "extended")
        self.assertIn("scattering_scale", py["free"])
        with self.assertRaisesRegex(ValueError, "model = 'extend' is unknown: choose paper or extended"):
            ss.fit_color(hex="c4a090", model="extend")
        with self.assertRaisesRegex(ValueError, "model = 'extend' is unknown"):
            ss.fit_spectrum([450.0, 550.0, 650.0], [0.3, 0.4, 0.5], model="extend")
        with self.assertRaisesRegex(ValueError, "melanin_blend_prior, melanin_blend_weight: not used by model = 'extended'"):
            ss.fit_color(hex="c4a090", model="extended", melanin_blend_prior=0.5)

    def test_fit_texture_with_the_extended_model(self):
        # The extended maps: one more map per other free parameter, named by its key, as the
        # command's channels; a colour the model makes inside the measured ranges is reached.
        target = ss.color(melanin=0.02, hemoglobin=0.02, epidermis_thickness=0.08, scattering_scale=1.3)
        maps = ss.fit_texture(np.tile(target["color"]["srgb_linear"], (2, 3, 1)), model="extended")
        self.assertEqual(maps["channels"], ["melanin", "melanin_blend", "hemoglobin", "error", "oxygenation",
                                            "epidermis_thickness", "dermis_scattering_scale", "scattering_scale"])
        for k in maps["channels"]:
            self.assertEqual(maps[k].shape, (2, 3), k)
            self.assertEqual(maps["axes"][k], ("y", "x"), k)
        self.assertLess(maps["error_delta_e_2000"]["max"], 0.5)
        self.assertTrue(np.all((maps["epidermis_thickness"] >= 0.04) & (maps["epidermis_thickness"] <= 0.15)))
        # uncertainty=True: one standard deviation per free parameter and texel, the command's
        # channels uncertainty.<key>; from the table's derivatives, within 8 % of the exact
        # colour fit's uncertainty for the same colour (measured 5.4 %, hemoglobin's: the two
        # fits end 5 % apart along the flat direction the priors settle, the dermis' scattering
        # with the scattering scale).
        withsd = ss.fit_texture(np.tile(target["color"]["srgb_linear"], (2, 3, 1)), model="extended", uncertainty=True)
        single = ss.fit_color(srgb=target["color"]["srgb8"], model="extended")
        for k in ["melanin", "melanin_blend", "hemoglobin", "oxygenation", "epidermis_thickness",
                  "dermis_scattering_scale", "scattering_scale"]:
            self.assertIn("uncertainty." + k, withsd["channels"])
            np.testing.assert_array_equal(withsd[k], maps[k])
            self.assertEqual(withsd["uncertainty." + k].shape, (2, 3))
            np.testing.assert_allclose(withsd["uncertainty." + k], single["uncertainty"][k], rtol=0.08)

    def test_fit_takes_the_papers_symbols(self):
        keys = ss.fit_color(hex="a98f74", solver="multipole", free=["melanin", "hemoglobin"],
                            bounds={"hemoglobin": (0.0, 0.05)})
        symbols = ss.fit_color(hex="a98f74", solver="multipole", free=["C_m", "C_h"], bounds={"C_h": (0.0, 0.05)})
        self.assertEqual(symbols, keys)
        with self.assertRaisesRegex(ValueError, "bounds of melanin are given twice"):
            ss.fit_color(hex="a98f74", solver="multipole", bounds={"melanin": (0.0, 0.1), "C_m": (0.0, 0.2)})
        with self.assertRaisesRegex(ValueError, "free parameter 'melanin' is listed twice"):
            ss.fit_color(hex="a98f74", solver="multipole", free=["C_m", "melanin"])

    def test_parameters(self):
        self.assertEqual(ss.parameters(), cli("parameters"))


class Arrays(unittest.TestCase):
    """Arrays of parameter sets: one call, every set on all cores, the same numbers as one call
    per set, axes named after the parameter varying along them."""

    def test_a_sweep_equals_one_call_per_set(self):
        melanin = np.linspace(0, 0.5, 6)
        s = ss.spectrum(melanin=melanin, lambda_step=10)
        self.assertEqual(s["R_d"].shape, (6, 31))
        self.assertEqual(s["axes"]["R_d"], ("melanin", "wavelength_nm"))
        self.assertEqual(s["axes"]["color.lab"], ("melanin", "Lab"))
        self.assertEqual(s["color"]["hex"].shape, (6,))
        np.testing.assert_array_equal(s["parameters"]["melanin"], melanin)
        self.assertEqual(s["parameters"]["hemoglobin"], 0.005)  # not varied: a number
        for i, m in enumerate(melanin):
            one = ss.spectrum(melanin=m, lambda_step=10)
            np.testing.assert_array_equal(s["R_d"][i], one["R_d"])  # bit for bit
            np.testing.assert_array_equal(s["color"]["lab"][i], one["color"]["lab"])
            self.assertEqual(s["color"]["hex"][i], one["color"]["hex"])

    def test_arrays_broadcast_to_a_grid(self):
        c = ss.color(melanin=np.array([0.01, 0.1, 0.3])[:, None], hemoglobin=[0.001, 0.05],
                     solver="multipole", threads=2)
        self.assertEqual(c["color"]["XYZ"].shape, (3, 2, 3))
        self.assertEqual(c["axes"]["color.XYZ"], ("melanin", "hemoglobin", "XYZ"))
        self.assertEqual(c["parameters"]["hemoglobin"].shape, (3, 2))
        one = ss.color(melanin=0.3, hemoglobin=0.05, solver="multipole")
        np.testing.assert_array_equal(c["color"]["XYZ"][2, 1], one["color"]["XYZ"])
        # More melanin is darker; in light skin more blood is redder (a* up).
        self.assertTrue(np.all(np.diff(c["color"]["lab"][:, :, 0], axis=0) < 0))
        self.assertGreater(c["color"]["lab"][0, 1, 1], c["color"]["lab"][0, 0, 1] + 2)
        serial = ss.color(melanin=np.array([0.01, 0.1, 0.3])[:, None], hemoglobin=[0.001, 0.05],
                          solver="multipole", threads=1)
        np.testing.assert_array_equal(serial["color"]["XYZ"], c["color"]["XYZ"])

    def test_rgb_profiles_of_many_sets(self):
        p = ss.rgb_profile(r_mm=[0.1, 1.0], C_m=[0.01, 0.02], lambda_step=20)
        self.assertEqual(p["R"].shape, (2, 3, 2))
        self.assertEqual(p["axes"]["R"], ("melanin", "channel", "r_mm"))
        self.assertEqual(p["validity"]["profile"].tolist(), [True, True])
        one = ss.rgb_profile(r_mm=[0.1, 1.0], C_m=0.02, lambda_step=20)
        np.testing.assert_array_equal(p["R"][1], one["R"])
        q = ss.profile(r_mm=[0.5], melanin=[0.01, 0.02], lambda_step=100, solver="multipole")
        self.assertEqual(q["R"].shape, (2, 4, 1))
        self.assertEqual(q["axes"]["R"], ("melanin", "wavelength_nm", "r_mm"))
        # Each set's place in the skin domain, as the command's validity.skin_domain of that set.
        d = ss.rgb_profile(r_mm=[0.5], melanin=[0.01, 0.6], lambda_step=100, solver="multipole")
        self.assertEqual(d["validity"]["skin_domain"].tolist(), [True, False])
        self.assertEqual(d["validity"]["outside_skin_domain"][0], [])
        self.assertEqual(d["validity"]["outside_skin_domain"][1],
                         ss.rgb_profile(r_mm=[0.5], melanin=0.6, lambda_step=100,
                                        solver="multipole")["validity"]["outside_skin_domain"])

    def test_each_set_is_the_one_set_document(self):
        # An array of sets holds, at each set's index, what the call for that set alone returns
        # (both converted from the command's documents), bit for bit: one set valid and in the
        # skin domain, one not (its validity has a reason and outside_skin_domain).
        thickness = [0.25, 0.002]
        for f, kw in ((ss.rgb_profile, {"r_mm": [0.5]}), (ss.profile, {"r_mm": [0.5, 1.0]}),
                      (ss.spectrum, {}), (ss.color, {"illuminant": "A"})):
            with self.subTest(f=f.__name__), warnings.catch_warnings():
                warnings.simplefilter("ignore")
                sets = f(epidermis_thickness=thickness, lambda_step=100, solver="multipole", **kw)
                for i, t in enumerate(thickness):
                    one = f(epidermis_thickness=t, lambda_step=100, solver="multipole", **kw)
                    self.assert_set(sets, one, i, "")

    def assert_set(self, sets, one, i, path):
        if isinstance(one, dict):
            keys = [k for k in one if k != "axes"]
            # The one set's keys; an array of sets has outside_skin_domain always (empty lists).
            self.assertEqual([k for k in sets if k not in ("axes", "outside_skin_domain")],
                             [k for k in keys if k != "outside_skin_domain"], path)
            for k in keys:
                self.assert_set(sets[k], one[k], i, f"{path}.{k}")
            return
        per_set = isinstance(sets, np.ndarray) and sets.shape[:1] == (2,) and (
            sets.dtype == object or sets.shape[1:] == np.shape(one))  # object: a list per set
        value = sets[i] if per_set else sets
        if isinstance(one, np.ndarray):
            self.assertEqual(value.dtype, one.dtype, path)
            np.testing.assert_array_equal(value, one, err_msg=path)
        else:
            self.assertEqual(value, one, path)

    def test_several_keywords_on_one_axis(self):
        s = ss.color(melanin=[0.01, 0.02], hemoglobin=[0.01, 0.02], solver="multipole")
        self.assertEqual(s["axes"]["color.lab"], ("set", "Lab"))

    def test_a_bad_element_is_the_commands_message(self):
        with self.assertRaisesRegex(ValueError, r"^melanin \(C_m\) = 2 is out of range: allowed range is \[0, 1\]$"):
            ss.spectrum(melanin=[0.1, 2.0])
        with self.assertRaisesRegex(ValueError, r"^melanin must be a number, not array\(\[ True, False\]\)$"):
            ss.spectrum(melanin=np.array([True, False]))
        with self.assertRaisesRegex(ValueError, "^hemoglobin must be a number, not "):
            ss.spectrum(hemoglobin=["0.1"])
        with self.assertRaises(ValueError):  # shapes that do not broadcast
            ss.spectrum(melanin=[0.1, 0.2], hemoglobin=[0.1, 0.2, 0.3])


class Bindings(unittest.TestCase):
    def test_version(self):
        self.assertRegex(ss.__version__, r"^\d+\.\d+\.\d+$")
        with open(os.path.join(SOURCE_DIR, "CMakeLists.txt")) as f:
            self.assertIn(f"project(spectral_skin VERSION {ss.__version__}", f.read())

    def test_the_stub_names_every_keyword_and_solver(self):
        stub = os.path.join(os.path.dirname(ss.__file__), "__init__.pyi")
        with open(stub) as f:
            text = f.read()
        for p in ss.parameters():
            self.assertIn(f"    {p['key']}: Number | None = ...,", text)
        self.assertIn("Solver = Literal[" + ", ".join(repr(s) for s in ss.solvers()) + "]", text)
        for name in ss.__all__:
            if name not in ("InputError", "__version__"):
                self.assertIn(f"def {name}(", text)
        compile(text, stub, "exec")  # valid Python syntax

    def test_docstrings_give_units_from_the_table(self):
        for f in (ss.spectrum, ss.color, ss.rgb_profile, ss.fit_spectrum):
            self.assertIn("epidermis_thickness [mm] in (0, inf), default 0.25", f.__doc__)
            self.assertIn("accurate, multipole, sfd", f.__doc__)

    def test_semi_infinite_layer_is_the_classic_dipole(self):
        # alpha' = 1 / 1.01, A(1.4) = 3.2507: Jensen et al. 2001 closed form.
        a = 1 / 1.01
        A = 3.250697461379377
        root = math.sqrt(3 * (1 - a))
        expected = a / 2 * (1 + math.exp(-4 / 3 * A * root)) * math.exp(-root)
        r = ss.layers([{"sigma_a": 0.01, "sigma_s_prime": 1.0}], solver="multipole")
        self.assertAlmostEqual(r["R_d"], expected, places=12)
        self.assertEqual(r["T_d"], 0.0)
        with self.assertRaisesRegex(ValueError, "^layer 1 sigma_a must be a number, not True$"):
            ss.layers([{"sigma_a": True, "sigma_s_prime": 1.0}])

    def test_spectrum_keywords_and_solvers(self):
        s = ss.spectrum("african", lambda_step=10, melanin=0.4)
        self.assertEqual(s["R_d"].shape, (31,))
        self.assertEqual(s["axes"]["R_d"], ("wavelength_nm",))
        self.assertEqual(s["solver"], "accurate")
        m = ss.spectrum("african", lambda_step=10, melanin=0.4, solver="multipole")
        self.assertGreater(m["R_d"][5], s["R_d"][5])  # diffusion overstates dark skin at 450 nm
        self.assertEqual(len(s["color"]["hex"]), 7)

    def test_profile_integrates_to_total(self):
        r = np.geomspace(1e-4, 60, 600)
        p = ss.rgb_profile("caucasian", r_mm=r)
        for c in range(3):
            R = p["R"][c]
            total = math.pi * r[0] ** 2 * R[0] + np.sum(math.pi * (R[:-1] * r[:-1] + R[1:] * r[1:]) * np.diff(r))
            self.assertAlmostEqual(total / p["R_d"][c], 1.0, delta=0.005)

    def test_validity_outside_the_accurate_tables(self):
        # A dark top layer (alpha' = 0.038) over a bright half-space, and skin with g = 0.6: off
        # the skin table, solved by radiative transfer in the spatial-frequency domain, inside
        # the model's range (no warning).
        layers = [{"sigma_a": 50.0, "sigma_s_prime": 2.0, "thickness": 0.05},
                  {"sigma_a": 0.001, "sigma_s_prime": 10.0}]
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            r = ss.layers(layers, r_mm=[0.3, 3.0])
            p = ss.rgb_profile("caucasian", r_mm=[0.3, 3.0], g=0.6, lambda_step=150)
        self.assertEqual(r["validity"]["profile"], True)
        self.assertEqual(p["validity"]["profile"], True)
        self.assertGreater(r["profile"]["R"][0] if "profile" in r else r["R"][0], 0)

    def test_fit_texture_of_a_uniform_image(self):
        target = ss.color("tanned")["color"]["srgb_linear"]
        maps = ss.fit_texture(np.tile(target, (2, 3, 1)), solver="multipole")
        self.assertEqual(maps["melanin"].shape, (2, 3))
        self.assertEqual(maps["axes"]["melanin"], ("y", "x"))
        self.assertEqual(maps["channels"], ["melanin", "melanin_blend", "hemoglobin", "error"])  # as the command's
        self.assertLess(maps["error_delta_e_2000"]["max"], 0.5)

    def test_the_tour_example_runs(self):
        # The Python example of the tour (docs/tour.md, moved there from the README).
        tour = os.path.join(SOURCE_DIR, "docs", "tour.md")
        with open(tour, encoding="utf-8") as f:
            text = f.read()
        section = text[text.index("\n## Python"):]
        section = section[:section.index("\n## ", 1)]
        blocks = section.split("```python\n")[1:]  # every block of the section, in one namespace
        self.assertIn("import spectral_skin", blocks[0])
        namespace = {}
        for block in blocks:
            exec(compile(block[:block.index("```\n")], "docs/tour.md (## Python)", "exec"), namespace)

    def test_bad_input_raises_value_error_naming_the_parameter(self):
        with self.assertRaisesRegex(ValueError, r"melanin \(C_m\) = 1.5 is out of range"):
            ss.spectrum(melanin=1.5)
        self.assertIn("ear", ss.presets())
        with self.assertRaisesRegex(ValueError, "^solver = 'diffusion' is unknown: allowed values are accurate, multipole, sfd$"):
            ss.color(solver="diffusion")


class EveryDoorHolds(unittest.TestCase):
    """Issue 29: input that crashed the interpreter, was defaulted silently or could not be stopped
    is a ValueError naming the parameter, as the command's line; long calls stop on Ctrl-C."""

    def test_empty_arrays_are_refused_not_a_crash(self):
        empty = "^melanin is an empty array \\(shape \\(0(, 3)?,?\\)\\): must be a number or an array of numbers with at least one element$"
        with self.assertRaisesRegex(ValueError, empty):
            ss.spectrum(melanin=[])
        with self.assertRaisesRegex(ValueError, empty):
            ss.color(melanin=np.zeros((0, 3)))
        with self.assertRaisesRegex(ValueError, empty):
            ss.rgb_profile(melanin=[], r_mm=[1])
        with self.assertRaisesRegex(ValueError, "^r_mm is empty: give at least one radius"):
            ss.profile(r_mm=[])
        with self.assertRaisesRegex(ValueError, "^the parameter arrays do not broadcast together .*: shapes melanin \\(2,\\), hemoglobin \\(3,\\)$"):
            ss.color(melanin=[0.1, 0.2], hemoglobin=[0.01, 0.02, 0.03])

    def test_whole_numbers_are_checked_as_the_command_checks_them(self):
        with self.assertRaisesRegex(ValueError, "^threads = 1000000 is out of range: must be a whole number in \\[0, 4096\\]$"):
            ss.spectrum(threads=10**6)
        with self.assertRaisesRegex(ValueError, "^threads = -1 is out of range"):
            ss.color(threads=-1)
        for photons in (0, -1, 10**30):
            with self.assertRaisesRegex(ValueError, f"^photons = {photons} is out of range: must be a whole number >= 1$"):
                ss.mc(wavelength=650, photons=photons)
        for photons in (1.5, True, "10", None):
            with self.assertRaisesRegex(ValueError, "^photons must be a whole number >= 1, not "):
                ss.mc(wavelength=650, photons=photons)
        with self.assertRaisesRegex(ValueError, "^bins = 0 is out of range: must be a whole number in \\[1, 1000000\\]$"):
            ss.mc(wavelength=650, photons=10, bins=0)
        self.assertEqual(ss.mc(wavelength=650, photons=np.int64(10), bins=np.uint8(4), threads=1)["photons"], 10)

    def test_layers_need_both_coefficients(self):
        with self.assertRaisesRegex(ValueError, "^layer 1: sigma_s_prime is missing: sigma_a and sigma_s_prime are required"):
            ss.layers([{"sigma_a": 1}])
        with self.assertRaisesRegex(ValueError, "^layer 1: sigma_a is missing: sigma_a and sigma_s_prime are required"):
            ss.layers([{}])
        with self.assertRaisesRegex(ValueError, "^layer 2: sigma_a is missing"):
            ss.mc(layers=[{"sigma_a": 1, "sigma_s_prime": 1, "thickness_mm": 1}, {"sigma_s_prime": 1}], photons=10)
        with self.assertRaisesRegex(ValueError, "^layers is empty"):
            ss.layers([])
        with self.assertRaisesRegex(ValueError, "^layer 1 eta is None: must be a number$"):
            ss.layers([{"sigma_a": 1, "sigma_s_prime": 1, "eta": None}])

    def test_a_huge_monte_carlo_run_is_refused_with_the_commands_line(self):
        line = (r"^a Monte Carlo run of 10000000000000 photons would take about [0-9.e+]+ (days|years) on 2 threads "
                r"\(estimate from the measured speed\): refused, make it smaller$")
        with self.assertRaisesRegex(ValueError, line):
            ss.mc(wavelength=650, photons=10**13, threads=2)
        if SKIN:
            out = subprocess.run([SKIN, "mc", "--wavelength", "650", "--photons", str(10**13), "--threads", "2"],
                                 capture_output=True, text=True)
            self.assertEqual(out.returncode, 2)
            self.assertRegex(out.stderr.strip().removeprefix("skin: error: "), line)

    def test_fit_texture_refuses_values_outside_0_1(self):
        image = np.full((2, 2, 3), 0.3)
        image[1, 0, 2] = np.nan
        with self.assertRaisesRegex(ValueError, r"^image\[1, 0, 2\] = nan is out of range: linear sRGB must be in \[0, 1\]$"):
            ss.fit_texture(image)
        image[1, 0, 2] = 1.5
        with self.assertRaisesRegex(ValueError, r"^image\[1, 0, 2\] = 1.5 is out of range"):
            ss.fit_texture(image)
        with self.assertRaisesRegex(ValueError, "^image must be a file name or an array of numbers of shape"):
            ss.fit_texture(np.zeros((0, 2, 3)))

    def test_fit_color_takes_a_sequence_of_three_numbers(self):
        text = ss.fit_color(srgb="169,143,116", solver="multipole")
        self.assertEqual(ss.fit_color(srgb=(169, 143, 116), solver="multipole"), text)
        self.assertEqual(ss.fit_color(srgb=np.array([169, 143, 116]), solver="multipole"), text)
        for bad in ((1, 2), [1, 2, 3, 4], "1,2", (1, 2, "x"), (True, 1, 2)):
            with self.assertRaises(ValueError):
                ss.fit_color(srgb=bad)
        with self.assertRaisesRegex(ValueError, "^srgb = 300 is out of range"):
            ss.fit_color(srgb=(300, 1, 2))

    def interrupted_after(self, seconds, call):
        """Sends SIGINT to this process after `seconds`; returns the seconds from it to the
        KeyboardInterrupt that `call` must raise."""
        import signal
        import threading
        import time
        sent = []
        # Python turns SIGINT into KeyboardInterrupt only if SIGINT was not ignored when it started
        # (a process started in the background by a non-interactive shell inherits it ignored).
        previous = signal.signal(signal.SIGINT, signal.default_int_handler)
        timer = threading.Timer(seconds, lambda: (sent.append(time.monotonic()), os.kill(os.getpid(), signal.SIGINT)))
        timer.start()
        try:
            with self.assertRaises(KeyboardInterrupt):
                call()
            return time.monotonic() - sent[0]
        finally:
            timer.cancel()
            signal.signal(signal.SIGINT, previous)

    def test_long_calls_stop_on_ctrl_c(self):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # "would take about ... hours"
            self.assertLess(self.interrupted_after(0.5, lambda: ss.mc(wavelength=650, photons=10**9)), 1.0)
        self.assertLess(self.interrupted_after(0.5, lambda: ss.color(melanin=np.linspace(0, 0.5, 200000))), 1.0)
        # A non-absorbing half-space: one photon can take seconds.
        clear = [{"sigma_a": 0, "sigma_s_prime": 1}]
        self.assertLess(self.interrupted_after(0.5, lambda: ss.mc(layers=clear, photons=10**6)), 1.0)
        self.assertEqual(ss.mc(wavelength=650, photons=100, threads=1)["photons"], 100)  # nothing left cancelled

    def test_a_profile_reports_its_progress_and_says_when_it_will_be_long(self):
        # Counted over every set's wavelengths, from the calling thread, ending at the total; the
        # numbers are those of the call without it.
        calls = []
        kw = dict(r_mm=[0.1, 1.0], melanin=[0.05, 0.2, 0.4])
        with_progress = ss.rgb_profile(**kw, progress=lambda done, total: calls.append((done, total)))
        self.assertEqual(calls[-1], (453, 453))
        self.assertEqual([d for d, _ in calls], sorted(d for d, _ in calls))
        self.assertTrue(all(t == 453 for _, t in calls))
        np.testing.assert_array_equal(with_progress["R"], ss.rgb_profile(**kw)["R"])
        self.assertEqual(ss.profile(r_mm=[0.1], lambda_min=600, lambda_max=620, lambda_step=10,
                                    progress=lambda d, t: calls.append((d, t)))["R"].shape, (3, 1))
        self.assertEqual(calls[-1], (3, 3))

        # A solve of every wavelength (sfd: ~1 s each) is announced with its estimate before it
        # starts, and an exception raised by the callback stops it at once and is raised.
        class Enough(Exception):
            pass

        def stop(done, total):
            raise Enough(f"{done} of {total}")

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            started = time.monotonic()
            with self.assertRaises(Enough):
                ss.rgb_profile(r_mm=[0.1], solver="sfd", progress=stop)
            self.assertLess(time.monotonic() - started, 5.0)
        said = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
        self.assertTrue(any(m.startswith("151 of the 151 wavelength profiles (off the skin and half-space tables, "
                                         "solved in the frequency domain) would take about ") for m in said), said)
        # A call read from the tables says nothing.
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            ss.rgb_profile(r_mm=[0.1])
        for bad in (3, "yes", [1]):
            with self.assertRaisesRegex(ValueError, r"^progress must be a callable progress\(done, total\) or None"):
                ss.rgb_profile(r_mm=[0.1], progress=bad)
            with self.assertRaisesRegex(ValueError, r"^progress must be a callable progress\(done, total\) or None"):
                ss.export("openpbr", progress=bad)
        # export: the same over its profile's 151 wavelengths, files as without it.
        calls.clear()
        exported = ss.export("openpbr", progress=lambda d, t: calls.append((d, t)))
        self.assertEqual(calls[-1], (151, 151))
        self.assertEqual(exported["files"], ss.export("openpbr")["files"])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            with self.assertRaises(Enough):
                ss.export("openpbr", solver="sfd", progress=stop)
        self.assertTrue(any(str(w.message).startswith("151 of the 151 wavelength profiles") for w in caught))
        self.assertEqual(ss.mc(wavelength=650, photons=100, threads=1)["photons"], 100)  # nothing left cancelled

    def test_a_non_absorbing_half_space_ends(self):
        r = ss.mc(layers=[{"sigma_a": 0, "sigma_s_prime": 1}], photons=200)
        self.assertAlmostEqual(r["R_d"] + r["lost"], 1.0, places=12)
        self.assertLess(r["lost"], 0.05)


def assert_row_is_the_single_call(test, many, single, i, path="", axes=None):
    """Row i of a call on N targets equals the single call on target i exactly (bit for bit): the
    values with a leading axis (named in many["axes"]) at i, the others as they are."""
    axes = many["axes"] if axes is None else axes
    keys = set(single) - {"axes"}
    test.assertEqual(keys, set(many) - {"axes"}, path)
    for k in keys:
        v, p = single[k], f"{path}.{k}" if path else k
        if isinstance(v, dict):
            assert_row_is_the_single_call(test, many[k], v, i, p, axes)
        elif p in axes and axes[p][0] in ("target", "spectrum"):
            got = np.asarray(many[k])[i]
            want = np.nan if v is None else v  # an uncertainty None (not finite) is NaN in a batch
            np.testing.assert_array_equal(got, np.asarray(want, dtype=got.dtype), err_msg=p)
            if got.dtype.kind == "f":  # the same bits, not merely equal
                test.assertEqual(np.asarray(want, dtype=float).tobytes(), got.tobytes(), p)
        else:
            if p not in axes:
                test.assertNotIsInstance(many[k], np.ndarray, f"{p} varies but has no axes")
            assert_equal(test, many[k], v)


class ManyFitsAtOnce(unittest.TestCase):
    """Issue 32, item 3: fit_color on N colours and fit_spectrum on N spectra are N single calls,
    bit for bit, computed on all cores without the GIL; fit_texture takes numpy arrays."""

    def test_n_colours_are_n_single_calls(self):
        srgb = np.array([[169, 143, 116], [250.5, 200.25, 180], [60, 40, 30], [0, 0, 0], [255, 255, 255]])
        many = ss.fit_color(srgb=srgb, solver="multipole")
        self.assertEqual(many["parameters"]["melanin"].shape, (5,))
        self.assertEqual(many["target"]["lab"].shape, (5, 3))
        self.assertEqual(many["axes"]["target.lab"], ("target", "Lab"))
        self.assertEqual(list(many["target"]["hex"]), ["#a98f74", "#fbc8b4", "#3c281e", "#000000", "#ffffff"])
        for i in range(len(srgb)):
            assert_row_is_the_single_call(self, many, ss.fit_color(srgb=srgb[i], solver="multipole"), i)
        # The same colours as texts, as 8-bit integers, on one thread: the same numbers.
        as_hex = ss.fit_color(hex=["a98f74", "#3c281e"], solver="multipole")
        assert_equal(self, as_hex["parameters"], ss.fit_color(srgb=srgb[[0, 2]], solver="multipole")["parameters"])
        one_thread = ss.fit_color(srgb=srgb[[0, 2]].astype(np.uint8), solver="multipole", threads=1)
        assert_equal(self, one_thread, ss.fit_color(srgb=srgb[[0, 2]], solver="multipole"))
        # One row is still N = 1 (arrays), not the single call's lists.
        self.assertEqual(ss.fit_color(srgb=srgb[:1], solver="multipole")["delta_e_2000"].shape, (1,))

    def test_n_colours_with_fixed_parameters_and_the_default_solver(self):
        srgb = np.array([[190, 150, 120], [120, 80, 60]])
        kw = {"free": ["melanin", "hemoglobin"], "melanin_blend": 0.5, "bounds": {"C_h": (0.001, 0.1)}}
        many = ss.fit_color(srgb=srgb, **kw)
        for i in range(len(srgb)):
            assert_row_is_the_single_call(self, many, ss.fit_color(srgb=srgb[i], **kw), i)
        np.testing.assert_array_equal(many["parameters"]["melanin_blend"], [0.5, 0.5])

    def test_n_spectra_are_n_single_calls(self):
        s = ss.spectrum(melanin=[0.02, 0.08, 0.25], hemoglobin=[0.01, 0.05, 0.002], lambda_step=10,
                        solver="multipole")
        rng = np.random.default_rng(3)
        R = np.clip(s["R_d"] + rng.normal(0, 0.003, s["R_d"].shape), 0, 1)
        for kw in ({}, {"includes_specular": True, "free": ["melanin", "hemoglobin", "oxygenation"]}):
            many = ss.fit_spectrum(s["wavelength_nm"], R, solver="multipole", **kw)
            self.assertEqual(many["fitted"]["R"].shape, (3, 31))
            self.assertEqual(many["axes"]["fitted.R"], ("spectrum", "wavelength_nm"))
            self.assertEqual(many["rms"].shape, (3,))
            for i in range(3):
                single = ss.fit_spectrum(s["wavelength_nm"], list(R[i]), solver="multipole", **kw)
                assert_row_is_the_single_call(self, many, single, i)

    def test_the_gil_is_released(self):
        import threading
        import time
        # 600 colours: ~0.85 s on two idle cores (120 took 0.17 s there, too short to tell)
        srgb = np.tile([[169, 143, 116], [90, 60, 45]], (300, 1)) + np.arange(600)[:, None] % 7
        done = []
        worker = threading.Thread(target=lambda: done.append(ss.fit_color(srgb=srgb, solver="multipole")))
        start = time.monotonic()
        worker.start()
        ticks, last, longest = 0, time.monotonic(), 0.0
        while worker.is_alive():  # this thread runs Python meanwhile
            now = time.monotonic()
            longest, last, ticks = max(longest, now - last), now, ticks + 1
        worker.join()
        self.assertGreater(time.monotonic() - start, 0.2)  # long enough to tell
        self.assertEqual(done[0]["parameters"]["melanin"].shape, (600,))
        self.assertLess(longest, 0.15)
        self.assertGreater(ticks, 1000)

    def test_ctrl_c_stops_them(self):
        interrupted_after = EveryDoorHolds.interrupted_after
        many = np.tile([[169, 143, 116], [90, 60, 45]], (5000, 1))
        self.assertLess(interrupted_after(self, 0.3, lambda: ss.fit_color(srgb=many, solver="multipole")), 1.0)
        s = ss.spectrum(melanin=0.1, lambda_step=10, solver="multipole")
        R = np.tile(s["R_d"], (20000, 1))
        self.assertLess(interrupted_after(self, 0.3, lambda: ss.fit_spectrum(s["wavelength_nm"], R, solver="multipole")),
                        1.0)
        self.assertEqual(ss.fit_color(srgb=many[:2], solver="multipole")["delta_e_2000"].shape, (2,))  # not left cancelled

    def test_bad_input_is_one_value_error_naming_the_parameter(self):
        wl = np.arange(400.0, 701.0, 20.0)
        R = np.full((2, 16), 0.4)
        cases = [
            (lambda: ss.fit_color(srgb=np.zeros((2, 4))), r"^srgb has shape \(2, 4\): N colours are an array of shape \(N, 3\)"),
            (lambda: ss.fit_color(srgb=np.zeros((0, 3))), r"^srgb is an empty array \(shape \(0, 3\)\): give at least one colour$"),
            (lambda: ss.fit_color(srgb=[[1, 2, 3], [4, 5, np.nan]]), r"^srgb\[1, 2\] = nan is out of range: allowed range is \[0, 255\]$"),
            (lambda: ss.fit_color(srgb=[[300, 2, 3]]), r"^srgb\[0, 0\] = 300 is out of range"),
            (lambda: ss.fit_color(srgb=[[-1, 2, 3]]), r"^srgb\[0, 0\] = -1 is out of range"),
            (lambda: ss.fit_color(srgb=np.zeros((2, 3, 1))), r"^srgb = .* must be three numbers R,G,B"),
            (lambda: ss.fit_color(srgb=np.zeros((2, 3), dtype=bool)), r"^srgb = .* must be three numbers R,G,B"),
            (lambda: ss.fit_color(hex=["a98f74", "zz"]), r"^hex\[1\]: hex = 'zz' must be six hexadecimal digits RRGGBB$"),
            (lambda: ss.fit_color(hex=[]), r"^hex is an empty sequence: give at least one colour$"),
            (lambda: ss.fit_color(hex=[1, 2]), r"^hex = \[1, 2\] must be a text RRGGBB or a sequence of them$"),
            (lambda: ss.fit_color(srgb=[[1, 2, 3]], threads=-1), r"^threads = -1 is out of range"),
            (lambda: ss.fit_spectrum(wl, np.full((2, 15), 0.4)), r"^R has shape \(2, 15\) but wavelength_nm has 16 values"),
            (lambda: ss.fit_spectrum(wl, np.zeros((0, 16))), r"^R is an empty array \(shape \(0, 16\)\): give at least one spectrum$"),
            (lambda: ss.fit_spectrum(wl, np.where(np.arange(32).reshape(2, 16) == 20, np.nan, R)),
             r"^spectrum 'R\[1\]': reflectance = nan at 480 nm is out of range: must be within \[0, 1\]$"),
            (lambda: ss.fit_spectrum(wl, R * 50), r"^spectrum 'R\[0\]': reflectance = 20 at 400 nm is out of range"),
            (lambda: ss.fit_spectrum(wl, np.full((1, 2, 16), 0.4)), r"^R must be a reflectance spectrum .* not an array of shape \(1, 2, 16\)$"),
            (lambda: ss.fit_spectrum(wl, [[0.4] * 16, [0.4]]), r"^R must be a reflectance spectrum"),
            (lambda: ss.fit_spectrum(wl, np.full(16, "x")), r"^R must be a reflectance spectrum"),
            (lambda: ss.fit_spectrum(wl, R, threads=10**6), r"^threads = 1000000 is out of range"),
        ]
        for call, message in cases:
            with self.assertRaisesRegex(ValueError, message):
                call()

    def test_fit_texture_takes_numpy_arrays_as_they_are(self):
        import pathlib
        rgb = np.array(ss.color("tanned", solver="multipole")["color"]["srgb_linear"])
        image = np.stack([np.tile(rgb, (3, 1)), np.tile(rgb * 0.8, (3, 1))]).astype(np.float32)  # (2, 3, 3)
        maps = ss.fit_texture(image, solver="multipole")
        for same in (image.astype(np.float64), np.asfortranarray(image), np.repeat(image, 2, axis=1)[:, ::2],
                     image.tolist()):
            again = ss.fit_texture(same, solver="multipole")
            for k in ("melanin", "melanin_blend", "hemoglobin", "error"):
                np.testing.assert_array_equal(again[k], maps[k], err_msg=k)
                self.assertEqual(again[k].dtype, np.float32)
        with self.assertRaisesRegex(ValueError, "no-such-albedo.png"):  # a path object is a file name
            ss.fit_texture(pathlib.Path("no-such-albedo.png"))


def write_png(path, rgb8):
    """A 8-bit RGB PNG of an array (height, width, 3) of uint8 (zlib, no image library)."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    h, w, _ = rgb8.shape
    rows = b"".join(b"\0" + rgb8[y].tobytes() for y in range(h))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def has_dask():
    try:
        import dask.distributed  # noqa: F401
        return True
    except ImportError:
        return False


@unittest.skipUnless(has_dask(), "dask is not importable: apt-get install python3-dask python3-distributed "
                                 "(scripts/install-deps.sh installs them)")
class OnADaskCluster(unittest.TestCase):
    """Issue 32, item 4: spectral_skin.distributed maps texture fits and parameter sweeps onto a
    Dask cluster (here two local worker processes); the results are those of the run on one
    machine, every number equal."""

    @classmethod
    def setUpClass(cls):
        import logging
        from dask.distributed import Client, LocalCluster
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)  # Debian's tornado and distributed 2022.12
            cls.cluster = LocalCluster(n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None,
                                       silence_logs=logging.ERROR)
        cls.client = Client(cls.cluster)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.cluster.close()

    def test_a_sweep_is_the_call_on_one_machine(self):
        import spectral_skin.distributed as sd
        grid = {"melanin": np.linspace(0, 0.5, 7)[:, None], "C_h": [0.002, 0.02, 0.05], "solver": "multipole",
                "lambda_step": 20}
        many = sd.sweep(self.client, "color", chunk_size=4, **grid)  # 21 sets in 6 tasks, rows split
        assert_equal(self, many, ss.color(**grid))
        self.assertEqual(many["color"]["lab"].shape, (7, 3, 3))
        profiles = {"melanin": [0.1, 0.3], "hemoglobin": np.array([[0.01], [0.03], [0.05]]), "r_mm": [0.1, 1.0],
                    "eta": np.float64(1.3), "solver": "multipole", "lambda_step": 50}
        assert_equal(self, sd.sweep(self.client, "rgb_profile", "african", chunk_size=1, **profiles),
                     ss.rgb_profile("african", **profiles))
        assert_equal(self, sd.sweep(self.client, "profile", chunk_size=5, **profiles), ss.profile(**profiles))
        layers = {"epidermis_thickness": [0.15, 0.25, 0.35], "lambda_step": 50, "solver": "multipole"}
        assert_equal(self, sd.sweep(self.client, "spectrum", chunk_size=2, **layers), ss.spectrum(**layers))
        one = {"melanin": 0.2, "solver": "multipole"}  # no arrays: one task
        assert_equal(self, sd.sweep(self.client, "spectrum", **one), ss.spectrum(**one))

    def test_texture_fits_are_the_calls_on_one_machine(self):
        import pathlib
        import spectral_skin.distributed as sd
        rng = np.random.default_rng(5)
        arrays = list(rng.uniform(0.02, 0.7, (3, 4, 5, 3)))
        with tempfile.TemporaryDirectory() as d:
            png = pathlib.Path(d) / "albedo.png"
            write_png(png, rng.integers(40, 230, (6, 4, 3), dtype=np.uint8))
            images = arrays + [png, str(png)]
            maps = sd.fit_textures(self.client, images, solver="multipole")
            self.assertEqual(len(maps), len(images))
            for got, image in zip(maps, images):
                assert_equal(self, got, ss.fit_texture(image, solver="multipole"))
        self.assertEqual(maps[-1]["melanin"].shape, (6, 4))

    def test_a_scheduler_address_instead_of_a_client(self):
        import spectral_skin.distributed as sd
        grid = {"melanin": [0.05, 0.1, 0.2], "solver": "multipole", "lambda_step": 50}
        assert_equal(self, sd.sweep(self.cluster.scheduler_address, "spectrum", chunk_size=2, **grid),
                     ss.spectrum(**grid))

    def test_bad_input_is_the_calls_value_error(self):
        import spectral_skin.distributed as sd
        with self.assertRaisesRegex(ValueError, r"^melanin \(C_m\) = 2 is out of range"):
            sd.sweep(self.client, "color", melanin=[0.1, 0.2, 2.0], chunk_size=1)
        with self.assertRaisesRegex(ValueError, r"^image\[0, 0, 0\] = 3 is out of range"):
            sd.fit_textures(self.client, [np.full((2, 2, 3), 0.5), np.full((2, 2, 3), 3.0)])
        with self.assertRaisesRegex(ValueError, "^the parameter arrays do not broadcast together"):
            sd.sweep(self.client, "color", melanin=[0.1, 0.2], hemoglobin=[0.01, 0.02, 0.03])
        with self.assertRaisesRegex(ValueError, "^function = 'fit_color' is not a sweep: one of spectrum, color"):
            sd.sweep(self.client, "fit_color", melanin=[0.1])
        with self.assertRaisesRegex(ValueError, "^chunk_size = 0 is out of range: must be a whole number >= 1$"):
            sd.sweep(self.client, "color", melanin=[0.1], chunk_size=0)
        with self.assertRaisesRegex(ValueError, "^images is empty"):
            sd.fit_textures(self.client, [])
        with self.assertRaisesRegex(ValueError, "^client = None must be a dask.distributed.Client or a scheduler address"):
            sd.fit_textures(None, [np.full((1, 1, 3), 0.5)])


class EveryArrayHasAxes(unittest.TestCase):
    def test_every_array_of_a_call_on_sets_has_its_axes_named(self):
        # result["axes"] names the axes of every array of a result (spectral_skin.distributed
        # relies on it to join the sets of its tasks): the validity of each set too.
        def arrays(d, prefix=""):
            for k, v in d.items():
                p = f"{prefix}.{k}" if prefix else k
                if isinstance(v, dict) and k != "axes":
                    yield from arrays(v, p)
                elif isinstance(v, np.ndarray):
                    yield p, v
        every = {p["key"]: [value_in_range(p), p["default"]] for p in ss.parameters()}
        for f, kw in ((ss.spectrum, {}), (ss.color, {}), (ss.rgb_profile, {"r_mm": [0.5]}),
                      (ss.profile, {"r_mm": [0.5]})):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                r = f(lambda_step=100, solver="multipole", **kw, **every)
            for path, a in arrays(r):
                self.assertIn(path, r["axes"], f.__name__)
                self.assertEqual(len(r["axes"][path]), a.ndim, f"{f.__name__} {path}")


@unittest.skipUnless(os.environ.get("SKIN_EXPECT_INSTALLED"), "set by scripts/test.sh in its venv")
class Installed(unittest.TestCase):
    """scripts/test.sh runs these tests in a virtual environment the package was pip-installed
    into: the package imported is that copy, with its metadata."""

    def test_imported_from_the_environment(self):
        import importlib.metadata
        import sys
        self.assertTrue(os.path.abspath(ss.__file__).startswith(os.path.abspath(sys.prefix)), ss.__file__)
        self.assertEqual(importlib.metadata.version("spectral_skin"), ss.__version__)
        self.assertTrue(os.path.exists(os.path.join(os.path.dirname(ss.__file__), "__init__.pyi")))


class Example(unittest.TestCase):
    def test_the_example_plots(self):
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            self.skipTest("matplotlib (python3-matplotlib) not installed")
        import sys
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "sweep.png")
            run = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "examples", "melanin_sweep.py"), out],
                                 capture_output=True, text=True, cwd=d)
            self.assertEqual(run.returncode, 0, run.stderr)
            self.assertIn("R_d (11, 151) axes ('melanin', 'wavelength_nm')", run.stdout)
            self.assertGreater(os.path.getsize(out), 10000)


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
        self.assertEqual(ss.solvers(), ["accurate", "multipole", "sfd"])

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
                assert_equal(self, by_symbol, by_key)
        with self.assertRaisesRegex(ValueError,
                                    "^melanin is given twice: melanin and C_m name the same"):
            self.spectrum(melanin=0.1, C_m=0.2)

    def test_keywords_change_the_physics(self):
        # Not only the echo: more melanin darkens the spectrum at every wavelength.
        base = ss.spectrum("caucasian", lambda_step=50, solver="multipole")
        dark = ss.spectrum("caucasian", lambda_step=50, solver="multipole", C_m=0.4)
        self.assertTrue(np.all(dark["R_d"] < base["R_d"]))
        profile = ss.rgb_profile("african", r_mm=[0.5], solver="multipole", C_h=0.2)
        self.assertEqual(profile["parameters"]["hemoglobin"], 0.2)

    def test_none_keeps_the_preset(self):
        assert_equal(self, self.spectrum(melanin=None, g=None, C_h=None), self.spectrum())

    def test_booleans_and_text_are_not_numbers(self):
        with self.assertRaisesRegex(ValueError, "^melanin must be a number, not True$"):
            self.spectrum(melanin=True)
        with self.assertRaisesRegex(ValueError, "^hemoglobin must be a number, not False$"):
            self.spectrum(C_h=False)
        with self.assertRaisesRegex(ValueError, "^eta must be a number, not '1.4'$"):
            self.spectrum(eta="1.4")
        self.assertEqual(self.spectrum(eta=2)["parameters"]["eta"], 2.0)  # an int is a number
        self.assertEqual(self.spectrum(eta=np.float32(2))["parameters"]["eta"], 2.0)

    def test_unknown_keyword_lists_the_known_keys(self):
        with self.assertRaises(ValueError) as e:
            self.spectrum(melanine=0.1)
        message = str(e.exception)
        self.assertTrue(message.startswith("parameter 'melanine' is unknown: known parameters are "))
        for p in ss.parameters():
            self.assertIn(p["key"], message)


if __name__ == "__main__":
    unittest.main()
