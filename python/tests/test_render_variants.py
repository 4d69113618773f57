"""mb.render(..., variants=[...]): several BRDFs along shared paths."""
import pathlib

import numpy as np

import microbrdf as mb

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _env(name):
    return str(ROOT / "data" / "envmaps" / name)


def _brdfs():
    return [mb.brdf(model="ggx", alpha_x=0.1, alpha_y=0.3, metal="Cu"),
            mb.brdf(model="beckmann", alpha=0.4, metal="Au"),
            mb.brdf(model="ellipsoid", alpha_x=0.2, alpha_y=0.25, metal="Al")]


def test_each_variant_estimates_its_own_render():
    # Image means within 1.5% of each BRDF rendered alone (MIS both sides; the noise of a
    # 16^2 x 256 spp mean is a few tenths of a percent).
    b = _brdfs()
    kw = dict(scene="sphere", size=16, spp=256, seed=3, threads=2, direct="mis",
              white_env=True, sphere_light=[((3, 3, 3), 1.5, (4, 4, 4))])
    imgs = mb.render(b[0], variants=b[1:], **kw)
    assert isinstance(imgs, list) and len(imgs) == 3
    for brdf, img in zip(b, imgs):
        alone = mb.render(brdf, **kw)
        assert img.shape == alone.shape == (16, 16, 3)
        np.testing.assert_allclose(img.mean(axis=(0, 1)), alone.mean(axis=(0, 1)), rtol=0.015)


def test_one_variant_alone_is_the_plain_render_and_weights_are_checked():
    b = _brdfs()
    kw = dict(scene="cylinders", size=12, spp=4, seed=2, threads=1, direct="mis")
    plain = mb.render(b[0], **kw)
    (same,) = mb.render(b[0], variants=[], **kw)
    np.testing.assert_array_equal(plain, same)
    try:
        mb.render(b[0], variants=b[1:], variant_weights=[1.0], **kw)
    except mb.InputError as e:
        assert "variant weights" in str(e)
    else:
        raise AssertionError("a weight list of the wrong length was accepted")


def test_light_sets_share_paths_and_each_estimates_its_own_render():
    # The same sphere under the courtyard (given as usual) and the studio map (a light set):
    # a list per set; each image's mean within 1.5% of that set rendered alone (MIS).
    b = _brdfs()
    kw = dict(scene="sphere", size=16, spp=256, seed=3, threads=2, direct="mis")
    sets = mb.render(b[0], envmap=_env("blender_courtyard.exr"),
                     light_sets=[{"envmap": _env("blender_studio.exr")}], **kw)
    assert isinstance(sets, list) and len(sets) == 2
    for img, name in zip(sets, ["blender_courtyard.exr", "blender_studio.exr"]):
        alone = mb.render(b[0], envmap=_env(name), **kw)
        assert img.shape == alone.shape == (16, 16, 3)
        np.testing.assert_allclose(img.mean(axis=(0, 1)), alone.mean(axis=(0, 1)), rtol=0.015)
    # With variants: the variants' images under the first lights, then the first BRDF's under
    # each further set.
    both = mb.render(b[0], variants=b[1:2], light_sets=[{"white_env": True}], size=8, spp=2,
                     threads=1)
    assert len(both) == 2 and len(both[0]) == 2 and both[1].shape == (8, 8, 3)
    try:  # a further set without light: no white sky made up for it
        mb.render(b[0], light_sets=[{}], size=8, spp=1)
    except mb.InputError as e:
        assert "light set 2" in str(e)
    else:
        raise AssertionError("an empty light set was accepted")
    try:
        mb.render(b[0], light_sets=[{"envmap_path": "x.exr"}], size=8, spp=1)
    except ValueError as e:
        assert "envmap_path" in str(e)
    else:
        raise AssertionError("an unknown light-set key was accepted")
