"""The Python module (CTest: Python.pytest, label `python`; python/CMakeLists.txt).

Small frames (64x36) on the default device (PoCL on the CPU unless $TILESHADE_DEVICE says
otherwise). Run in place: PYTHONPATH=build/python python3 -m pytest -q python/tests
"""
import math
import os
import re
import subprocess

import numpy as np
import pytest

import tileshade

W, H = 64, 36


@pytest.fixture(scope="module")
def device():
    return tileshade.Device()


@pytest.fixture(scope="module")
def street(device):
    return tileshade.Frame.from_scene(device, width=W, height=H, light_count=40)


def binary():
    """The build's tileshade binary (CTest sets TILESHADE_BINARY), or None."""
    path = os.environ.get("TILESHADE_BINARY", "")
    return path if path and os.access(path, os.X_OK) else None


def test_version_is_the_binarys():
    assert re.fullmatch(r"\d+\.\d+\.\d+", tileshade.__version__)
    exe = binary()
    if exe:
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, check=True)
        assert out.stdout.strip() == "tileshade " + tileshade.__version__


def test_devices_and_techniques(device):
    devices = tileshade.devices()
    assert devices, "no OpenCL device"
    assert {"index", "platform", "name", "type", "compute_units"} <= set(devices[0])
    assert device.type in {"gpu", "cpu", "accelerator", "other"}
    assert " / " in device.name
    names = [t["name"] for t in tileshade.techniques()]
    assert {"tiled", "clustered", "deferred"} <= set(names)
    assert all(t["description"] for t in tileshade.techniques())
    # The registry's flags, as the C++ API's TechniqueDescription gives them.
    by_name = {t["name"]: t for t in tileshade.techniques()}
    assert by_name["tiled-forward"]["draws_scene"] and not by_name["tiled"]["draws_scene"]
    assert by_name["deferred"]["reuses_shadow_maps"] and not by_name["tiled"]["reuses_shadow_maps"]
    assert by_name["tiled"]["hybrid_transparency"] and not by_name["clustered"]["hybrid_transparency"]
    assert by_name["tiled-forward"]["multisamples"] and not by_name["forward"]["multisamples"]


def test_render_returns_an_image_and_stats():
    image, stats = tileshade.render(width=W, height=H, light_count=30, tile=8)
    assert image.shape == (H, W, 3)
    assert image.dtype == np.float32
    assert np.isfinite(image).all()
    assert image.max() > 0.0, "a lit street renders black"
    assert stats["technique"] == "tiled"
    assert stats["settings"]["tile"] == (8, 8)
    assert stats["frame"]["width"] == W and stats["frame"]["height"] == H
    assert stats["frame"]["lights"] == 30
    assert stats["frame"]["light_summary"].startswith("30 lights")
    assert 0 < stats["frame"]["geometry_pixels"] <= W * H
    assert stats["kernels"] and all(k["ms"] >= 0.0 for k in stats["kernels"])
    assert stats["total_ms"] == pytest.approx(sum(k["ms"] for k in stats["kernels"]))
    assert stats["counters"]["lighting_computations"] > 0
    assert stats["check"] is None


def test_shadow_knobs_draw_maps_and_shade_them(device):
    kw = dict(scene="builtin:atrium", lights="big", width=W, height=H, device=device)
    lit, plain = tileshade.render(**kw)
    shadowed, stats = tileshade.render(shadows=3, shadow_map_size=32, shadow_filter="pcf3",
                                       shadow_bias=(2.0, 1.0), shadow_budget=16, check=True, **kw)
    frame = stats["frame"]
    assert plain["frame"]["shadow_maps"] is None
    assert frame["shadow_casting_lights"] == 3
    maps = frame["shadow_maps"]
    assert len(maps["lights"]) == 3 and all(l["size"] == 32 for l in maps["lights"])
    assert maps["bytes"] == maps["atlas_width"] * maps["atlas_height"] * 4
    assert stats["check"]["missed"] == 0
    # A shadow only takes light away, and these three take some.
    assert (shadowed <= lit + 1e-6).all() and shadowed.sum() < lit.sum()
    with pytest.raises(TypeError, match=r"shadow_bias: expected a \(constant, slope\) pair"):
        tileshade.render(shadow_bias=3, **kw)
    with pytest.raises(tileshade.Error, match=r"--shadow-filter"):
        tileshade.render(shadows="all", shadow_filter="pcf4", **kw)


def test_two_techniques_agree_and_miss_nothing(device, street):
    tiled = tileshade.Renderer(device, "tiled", tile=(16, 8)).shade(street, check=True)
    clustered = tileshade.Renderer(device, technique="clustered", slices=8).shade(street,
                                                                                check=True)
    for result in (tiled, clustered):
        assert result.image.shape == (H, W, 4)
        assert result.check["missed"] == 0
        assert result.check["contributing"] > 0
        assert result.check["error"]["pixels_above_tolerance"] == 0
    peak = float(np.abs(tiled.image[..., :3]).max())
    assert peak > 0.0
    diff = float(np.abs(tiled.image - clustered.image).max())
    assert diff <= 2e-5 * peak, f"tiled and clustered differ by {diff} (peak {peak})"
    stats = clustered.stats()
    assert stats["technique"] == "clustered"
    assert stats["check"]["missed"] == 0


def test_result_image_is_a_view_of_the_result(device, street):
    result = tileshade.Renderer(device, "tiled").shade(street)
    image = result.image
    del result  # the array keeps the result's memory alive
    assert image.base is not None
    assert np.isfinite(image).all()


def blinn_phong(camera, x, y, depth, n, kd, ks, shininess, light, ambient):
    """One pixel of kernels/shading.h's model in float64, written again from its header comment:
    P from ts_view_position (pixel centres at +0.5, row 0 at the top), V = normalize(-P);
    window = clamp(1 - (d/r)^4, 0, 1)^2, falloff = window / max(d^2, dmin^2) with dmin = 0.1;
    wd = max(N.l, 0) * falloff, ws = wd * max(N.h, 0)^s with h = normalize(l + V);
    pixel = ke + ambient * kd + C (wd kd + ws ks)."""
    ndc_x = 2.0 * (x + 0.5) / camera.width - 1.0
    ndc_y = 1.0 - 2.0 * (y + 0.5) / camera.height
    p = np.array([ndc_x * camera.tan_half_fov_x * depth, ndc_y * camera.tan_half_fov_y * depth,
                  -depth])
    v = -p / np.linalg.norm(p)
    to_light = np.array(light["position"]) - p
    d2 = float(to_light @ to_light)
    l = to_light / math.sqrt(d2)
    window = min(max(1.0 - (d2 / light["range"] ** 2) ** 2, 0.0), 1.0) ** 2
    falloff = window / max(d2, 0.1 ** 2)
    wd = max(float(n @ l), 0.0) * falloff
    h = (l + v) / np.linalg.norm(l + v)
    ws = wd * max(float(n @ h), 0.0) ** shininess
    return np.array(ambient) * kd + np.array(light["color"]) * (wd * kd + ws * ks)


def plane_gbuffer(depth=5.0):
    """A plane facing the camera at linear depth `depth`, one material, fp32 planes."""
    planes = {
        "depth": np.full((H, W), depth, np.float32),
        "normal": np.zeros((H, W, 4), np.float32),
        "diffuse": np.zeros((H, W, 4), np.float32),
        "specular": np.zeros((H, W, 4), np.float32),
    }
    planes["normal"][..., 2] = 1.0
    planes["diffuse"][..., :3] = (0.6, 0.4, 0.2)
    planes["specular"][..., :3] = (0.3, 0.3, 0.3)
    planes["specular"][..., 3] = 16.0  # shininess
    return planes


def test_from_numpy_gives_the_analytic_blinn_phong_value(device):
    planes = plane_gbuffer()
    camera = tileshade.Camera.perspective(W, H, 0.9, 0.1, 100.0)
    light = {"type": "point", "position": [0.5, 0.3, -4.0], "color": [2.0, 1.5, 1.0],
             "range": 6.0}
    ambient = (0.05, 0.04, 0.03)
    frame = tileshade.Frame.from_numpy(device, planes["depth"], planes["normal"],
                                       planes["diffuse"], planes["specular"], camera=camera,
                                       lights=[light], ambient=ambient)
    assert frame.info["source"] == "host"
    assert frame.info["lights"] == 1
    image = tileshade.Renderer(device, "tiled").shade(frame).image
    kd, ks = np.array([0.6, 0.4, 0.2]), np.array([0.3, 0.3, 0.3])
    n = np.array([0.0, 0.0, 1.0])
    peak = float(image[..., :3].max())
    assert peak > 0.1
    # The pixel under the light, a corner and one in between: float kernels against float64.
    for x, y in [(40, 14), (0, 0), (W - 1, H - 1), (20, 30)]:
        expected = blinn_phong(camera, x, y, 5.0, n, kd, ks, 16.0, light, ambient)
        np.testing.assert_allclose(image[y, x, :3], expected, rtol=0, atol=2e-5 * peak,
                                   err_msg=f"pixel ({x}, {y})")
    # The same light as a tileshade.Light gives the same image.
    same = tileshade.Frame.from_numpy(device, planes["depth"], planes["normal"],
                                      planes["diffuse"], planes["specular"],
                                      camera={"yfov": 0.9, "znear": 0.1, "zfar": 100.0},
                                      lights=[tileshade.Light.point([0.5, 0.3, -4.0],
                                                                    [2.0, 1.5, 1.0], 6.0)],
                                      ambient=ambient)
    np.testing.assert_array_equal(tileshade.Renderer(device, "tiled").shade(same).image, image)


def test_from_numpy_refuses_a_wrong_dtype_shape_or_order(device):
    p = plane_gbuffer()
    camera = tileshade.Camera.perspective(W, H, 0.9, 0.1, 100.0)
    lights = [tileshade.Light.point([0, 0, -4], [1, 1, 1], 5)]

    def make(**override):
        args = dict(p, **override)
        return tileshade.Frame.from_numpy(device, args["depth"], args["normal"], args["diffuse"],
                                          args["specular"], camera=camera, lights=lights)

    with pytest.raises(ValueError, match=r"depth: .*float32.*got float64"):
        make(depth=p["depth"].astype(np.float64))
    with pytest.raises(ValueError, match=r"normal: .*\(36, 64, 4\).*got float32 of shape \(36, 64, 3\)"):
        make(normal=np.ascontiguousarray(p["normal"][..., :3]))
    with pytest.raises(ValueError, match=r"diffuse: .*\(36, 64, 4\)"):
        make(diffuse=p["diffuse"][:10])
    with pytest.raises(ValueError, match=r"specular: .*C-contiguous"):
        make(specular=np.asfortranarray(p["specular"]))
    with pytest.raises(ValueError, match=r"normal: expected a numpy"):
        make(normal=p["normal"].tolist())
    # fp16 planes must be float16.
    with pytest.raises(ValueError, match=r"normal: .*float16"):
        tileshade.Frame.from_numpy(device, p["depth"], p["normal"], p["diffuse"], camera=camera,
                                   lights=lights, layout="fp16")
    with pytest.raises(ValueError, match=r"light 0: unknown key 'radius'"):
        tileshade.Frame.from_numpy(device, p["depth"], p["normal"], p["diffuse"], camera=camera,
                                   lights=[{"type": "point", "position": [0, 0, -4],
                                            "color": [1, 1, 1], "range": 5, "radius": 1}])


def test_fp16_planes_shade_like_fp32(device):
    p = plane_gbuffer()
    camera = tileshade.Camera.perspective(W, H, 0.9, 0.1, 100.0)
    lights = [tileshade.Light.point([0.5, 0.3, -4.0], [2, 2, 2], 6.0)]
    renderer = tileshade.Renderer(device, "tiled")
    f32 = tileshade.Frame.from_numpy(device, p["depth"], p["normal"], p["diffuse"], p["specular"],
                                     camera=camera, lights=lights)
    f16 = tileshade.Frame.from_numpy(device, p["depth"], *(p[k].astype(np.float16)
                                                           for k in ("normal", "diffuse",
                                                                     "specular")),
                                     camera=camera, lights=lights, layout="fp16")
    assert f16.info["layout"] == "fp16"
    a, b = renderer.shade(f32).image, renderer.shade(f16).image
    # The material values are exact in half except 0.6, 0.4, 0.3 (rounded by < 2^-11 relative).
    assert np.abs(a - b).max() <= 1e-3 * a.max()


def test_a_bad_technique_is_tileshade_error_with_the_commands_line(device):
    with pytest.raises(tileshade.Error) as caught:
        tileshade.Renderer(device, "no-such-technique")
    message = str(caught.value)
    assert isinstance(caught.value, RuntimeError)
    assert "\n" not in message and "no-such-technique" in message
    exe = binary()
    if exe:
        out = subprocess.run([exe, "render", "--technique", "no-such-technique", "--width", "16",
                              "--height", "16"], capture_output=True, text=True)
        assert out.returncode != 0
        assert out.stderr.strip().splitlines()[-1] == "tileshade: error: " + message


def test_unknown_or_mistyped_keywords_name_the_knob(device):
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'tile_size'"):
        tileshade.render(width=W, height=H, tile_size=8)
    with pytest.raises(TypeError, match=r"width: expected an int, got str"):
        tileshade.render(width="64", height=H)
    with pytest.raises(TypeError, match=r"normal_maps: expected a bool, got str"):
        tileshade.render(width=W, height=H, normal_maps="off")
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'width'"):
        tileshade.Renderer(device, "tiled", width=64)  # a scene knob, not a technique's
    with pytest.raises(ValueError, match=r"tile: 'sixteen' is no tile size"):
        tileshade.Renderer(device, "tiled", tile="sixteen")
    with pytest.raises(tileshade.Error):
        tileshade.Renderer(device, "tiled", culling="no-such-test")


def test_shadow_storage_per_light_is_for_traditional_deferred(device):
    # Where the shadow maps live (docs/shadows.md): per-light is refused by a technique that
    # needs every map resident, taken by deferred; a frame without casters draws none.
    with pytest.raises(tileshade.Error) as caught:
        tileshade.Renderer(device, "tiled", shadow_storage="per-light")
    assert "needs every map resident" in str(caught.value)
    with pytest.raises(tileshade.Error, match=r"--shadow-storage"):
        tileshade.Renderer(device, "deferred", shadow_storage="per-tile")
    renderer = tileshade.Renderer(device, "deferred", shadow_storage="per-light")
    assert renderer.settings["shadow_storage"] == "per-light"
    p = plane_gbuffer()
    camera = tileshade.Camera.perspective(W, H, 0.9, 0.1, 100.0)
    lights = [tileshade.Light.point([0.5, 0.3, -4.0], [2, 2, 2], 6.0)]
    frame = tileshade.Frame.from_numpy(device, p["depth"], p["normal"], p["diffuse"],
                                       p["specular"], camera=camera, lights=lights)
    result = renderer.shade(frame)
    assert result.stats()["shadow_use"] is None
    np.testing.assert_array_equal(result.image, tileshade.Renderer(device, "deferred")
                                  .shade(frame).image)


def test_bench_returns_rows_with_numbers(tmp_path):
    config = {"scene": "builtin:street", "resolution": f"{W}x{H}", "light_count": 20,
              "technique": ["tiled", "clustered"], "frames": "1", "warmup": 0, "repeat": 1}
    rows = tileshade.bench(config, str(tmp_path / "bench"))
    assert len(rows) == 2
    assert {r["technique"] for r in rows} == {"tiled", "clustered"}
    for row in rows:
        assert isinstance(row["config_id"], str)
        assert isinstance(row["frame"], int)
        assert isinstance(row["total_ms"], float) and row["total_ms"] > 0.0
        assert isinstance(row["lighting_computations"], int)
    # The columns in bench.csv's order.
    header = (tmp_path / "bench" / "bench.csv").read_text().splitlines()[0].split(",")
    assert list(rows[0])[:len(header)] == header


def test_bench_dataframe_needs_pandas(tmp_path):
    config = {"resolution": f"{W}x{H}", "light_count": 10, "technique": "tiled", "frames": "1",
              "warmup": 0}
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="pandas"):
            tileshade.bench_dataframe(config, str(tmp_path / "df"))
    else:
        frame = tileshade.bench_dataframe(config, str(tmp_path / "df"))
        assert len(frame) == 1 and frame["total_ms"].dtype.kind == "f"
