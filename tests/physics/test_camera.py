"""Tests of the differentiable camera (thesis §7.3.3.1; src/thesis/physics/camera.py, raycast.py).

Oracles: closed-form pinhole geometry (silhouette radius of a sphere, head-on box face,
horizon row of a ground plane), bilinear interpolation computed by hand in NumPy float64
from the documented texture conventions, projection vs. ray casting, and float64 central
finite differences for gradients.
"""

import contextlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from thesis.physics.camera import camera_rays, project
from thesis.physics.raycast import Scene
from thesis.physics.raycast import cast as _cast

cast = jax.jit(_cast)  # compiled once per scene structure; eager dispatch is slow

BG = (0.0, 0.75, 1.0)


@pytest.fixture(autouse=True)
def _strict_numpy():
    """Strict rank and dtype promotion while these tests run (STYLE §7)."""
    old_rank = jax.config.jax_numpy_rank_promotion
    old_dtype = jax.config.jax_numpy_dtype_promotion
    jax.config.update("jax_numpy_rank_promotion", "raise")
    jax.config.update("jax_numpy_dtype_promotion", "strict")
    yield
    jax.config.update("jax_numpy_rank_promotion", old_rank)
    jax.config.update("jax_numpy_dtype_promotion", old_dtype)


@contextlib.contextmanager
def x64():
    old = jax.config.jax_enable_x64
    jax.config.update("jax_enable_x64", True)
    try:
        yield
    finally:
        jax.config.update("jax_enable_x64", old)


def make_scene(spheres=(), boxes=(), planes=(), textures=None, background=BG, dtype=np.float32):
    """Scene from lists of dicts (sphere: pos, r, rot, color, tex; box: pos, rot, half, color,
    tex; plane: pos, rot, color, tile, tex)."""

    def arr(items, key, shape, default=None):
        vals = [np.asarray(it.get(key, default), np.float64) for it in items]
        return jnp.asarray(np.stack(vals).reshape((len(items),) + shape)
                           if vals else np.zeros((0,) + shape), dtype)

    eye = np.eye(3)
    tex = np.zeros((0, 1, 1, 3)) if textures is None else np.asarray(textures)
    return Scene(
        sphere_pos=arr(spheres, "pos", (3,)), sphere_radius=arr(spheres, "r", ()),
        sphere_rot=arr(spheres, "rot", (3, 3), eye), sphere_color=arr(spheres, "color", (3,)),
        box_pos=arr(boxes, "pos", (3,)), box_rot=arr(boxes, "rot", (3, 3), eye),
        box_half=arr(boxes, "half", (3,)), box_color=arr(boxes, "color", (3,)),
        plane_pos=arr(planes, "pos", (3,)), plane_rot=arr(planes, "rot", (3, 3), eye),
        plane_color=arr(planes, "color", (3,)), plane_tile=arr(planes, "tile", (2,), (1, 1)),
        textures=jnp.asarray(tex, dtype), background=jnp.asarray(background, dtype),
        sphere_texture=tuple(int(s.get("tex", -1)) for s in spheres),
        box_texture=tuple(int(b.get("tex", -1)) for b in boxes),
        plane_texture=tuple(int(p.get("tex", -1)) for p in planes),
    )


def rot_from_seed(seed):
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def sensor_grid(focal, sensor, pixels):
    """Sensor coordinates (m) of the pixel centres: xs (W,), ys (H,)."""
    w, h = pixels
    xs = ((np.arange(w) + 0.5) / w - 0.5) * sensor[0]
    ys = ((np.arange(h) + 0.5) / h - 0.5) * sensor[1]
    return xs, ys


def hit_mask(img, bg=BG):
    return np.any(np.abs(np.asarray(img) - np.asarray(bg, np.float32)) > 1e-6, axis=-1)


# ----------------------------------------------------------------------------- geometry

CAM = dict(focal=0.03, sensor=(0.036, 0.027), pixels=(64, 48))  # square 0.5625 mm pixels


@pytest.mark.parametrize("seed", [None, 3])
def test_sphere_straight_ahead_centred_with_expected_pixel_radius(seed):
    f, sensor, pixels = CAM["focal"], CAM["sensor"], CAM["pixels"]
    pos = np.zeros(3) if seed is None else np.array([0.3, -1.2, 2.0])
    rot = np.eye(3) if seed is None else rot_from_seed(seed)
    dist, r = 4.0, 0.55
    scene = make_scene(spheres=[dict(pos=pos + rot @ [0, 0, dist], r=r, color=(1, 0, 0))])
    o, d = camera_rays(jnp.asarray(pos, jnp.float32), jnp.asarray(rot, jnp.float32),
                       f, sensor, pixels)
    img = np.asarray(cast(o, d, scene))
    assert img.shape == (48, 64, 3) and img.dtype == np.float32
    mask = hit_mask(img)
    pitch = sensor[0] / pixels[0]
    r_px = f * r / np.sqrt(dist**2 - r**2) / pitch  # silhouette radius f tan(asin(r/D))
    xs, ys = sensor_grid(f, sensor, pixels)
    rho = np.hypot(xs[None, :], ys[:, None]) / pitch
    decided = np.abs(rho - r_px) > 1e-3
    assert decided.sum() > 0.99 * mask.size
    np.testing.assert_array_equal(mask[decided], (rho < r_px)[decided])
    ii, jj = np.nonzero(mask)
    assert abs(jj.mean() - (pixels[0] - 1) / 2) < 1e-9
    assert abs(ii.mean() - (pixels[1] - 1) / 2) < 1e-9
    np.testing.assert_allclose(img[mask], np.tile([1, 0, 0], (mask.sum(), 1)))


@pytest.mark.parametrize("yaw90", [False, True])
def test_box_face_head_on_fills_expected_rectangle(yaw90):
    f, sensor, pixels = CAM["focal"], CAM["sensor"], CAM["pixels"]
    dist, half = 3.0, np.array([0.61, 0.37, 0.4])
    rot = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]) if yaw90 else np.eye(3)
    scene = make_scene(boxes=[dict(pos=(0, 0, dist + half[2]), rot=rot, half=half,
                                   color=(0, 1, 0))])
    o, d = camera_rays(jnp.zeros(3), jnp.eye(3), f, sensor, pixels)
    mask = hit_mask(cast(o, d, scene))
    hx, hy = (half[1], half[0]) if yaw90 else (half[0], half[1])
    xs, ys = sensor_grid(f, sensor, pixels)
    expected = (np.abs(xs[None, :]) < f * hx / dist) & (np.abs(ys[:, None]) < f * hy / dist)
    np.testing.assert_array_equal(mask, expected)
    rows, cols = np.nonzero(expected)
    assert 0 < rows.min() and rows.max() < pixels[1] - 1  # the rectangle is inside the image
    assert 0 < cols.min() and cols.max() < pixels[0] - 1


def test_ground_plane_splits_image_at_horizon_row():
    f, sensor, pixels = CAM["focal"], CAM["sensor"], CAM["pixels"]
    theta = np.deg2rad(12.0)  # camera pitched down
    c, s = np.cos(theta), np.sin(theta)
    right, forward = np.array([0, -1.0, 0]), np.array([c, 0, -s])
    down = np.cross(forward, right)
    rot = np.stack([right, down, forward], axis=1)
    assert np.isclose(np.linalg.det(rot), 1.0)
    scene = make_scene(planes=[dict(pos=(0, 0, 0), color=(0.3, 0.6, 0.1))])
    o, d = camera_rays(jnp.array([0, 0, 1.0]), jnp.asarray(rot, jnp.float32), f, sensor, pixels)
    mask = hit_mask(cast(o, d, scene))
    _, ys = sensor_grid(f, sensor, pixels)
    first_ground_row = int(np.argmax(ys > -f * np.tan(theta)))  # horizon at y = -f tan(theta)
    assert 0 < first_ground_row < pixels[1] // 2
    np.testing.assert_array_equal(mask[first_ground_row:], True)
    np.testing.assert_array_equal(mask[:first_ground_row], False)


def test_nearest_of_overlapping_objects_wins_regardless_of_order():
    f, sensor, pixels = CAM["focal"], CAM["sensor"], CAM["pixels"]
    near = dict(pos=(0, 0, 5.0), r=0.3, color=(1, 0, 0))
    far = dict(pos=(0.3, 0, 9.0), r=2.0, color=(0, 0, 1))
    box = dict(pos=(0, 0, 6.5), half=(0.6, 0.6, 0.4), color=(0, 1, 0))  # between both
    o, d = camera_rays(jnp.zeros(3), jnp.eye(3), f, sensor, pixels)
    img1 = np.asarray(cast(o, d, make_scene(spheres=[near, far], boxes=[box])))
    img2 = np.asarray(cast(o, d, make_scene(spheres=[far, near], boxes=[box])))
    np.testing.assert_array_equal(img1, img2)
    np.testing.assert_array_equal(img1[24, 32], [1, 0, 0])  # centre: the near sphere
    # Silhouette radii in pixels: near sphere ~3.2, box face ~5.2 (square), far sphere ~12.
    pitch = sensor[0] / pixels[0]
    r_near = f * 0.3 / np.sqrt(25 - 0.09) / pitch
    r_box = f * 0.6 / 6.1 / pitch
    xs, ys = sensor_grid(f, sensor, pixels)
    col_x = xs / pitch
    j_box = int(np.nonzero((col_x > r_near + 0.5) & (col_x < r_box - 0.5))[0][0])
    np.testing.assert_array_equal(img1[24, j_box], [0, 1, 0])
    np.testing.assert_array_equal(img1[24, 32 + 8], [0, 0, 1])
    assert np.all(hit_mask(img1)[24, 24:44]) and not hit_mask(img1)[24, 10]


# ----------------------------------------------------------------------------- textures


def bilinear_by_hand(tex, u, v, wrap_u, wrap_v):
    """Bilinear sample at texture coords (u, v); texel centres at ((j+.5)/w, (i+.5)/h)."""
    h, w, _ = tex.shape
    x, y = u * w - 0.5, v * h - 0.5
    j0, i0 = int(np.floor(x)), int(np.floor(y))
    fx, fy = x - j0, y - i0

    def fix(k, n, wrap):
        return k % n if wrap else min(max(k, 0), n - 1)

    j0w, j1w = fix(j0, w, wrap_u), fix(j0 + 1, w, wrap_u)
    i0w, i1w = fix(i0, h, wrap_v), fix(i0 + 1, h, wrap_v)
    return ((1 - fy) * ((1 - fx) * tex[i0w, j0w] + fx * tex[i0w, j1w])
            + fy * ((1 - fx) * tex[i1w, j0w] + fx * tex[i1w, j1w]))


PIXELS_TO_CHECK = [(0, 0), (5, 7), (11, 30), (24, 32), (30, 45), (47, 63), (17, 2)]


def _textures(seed, shape=(2, 5, 7, 3)):
    return np.random.default_rng(seed).uniform(0.1, 1.0, size=shape)


def test_plane_texture_is_tiled_bilinear_sample_computed_by_hand():
    f, sensor, pixels = CAM["focal"], CAM["sensor"], CAM["pixels"]
    tex = _textures(0)
    dist, origin, tile, color = 2.0, np.array([0.013, -0.021, 2.0]), (0.17, 0.11), (0.9, 0.8, 0.7)
    # Plane facing the camera: texture right = world +x, texture up = world -y (camera up).
    rot = np.stack([[1, 0, 0], [0, -1, 0], [0, 0, -1.0]], axis=1)
    scene = make_scene(planes=[dict(pos=origin, rot=rot, tile=tile, color=color, tex=1)],
                       textures=tex)
    o, d = camera_rays(jnp.zeros(3), jnp.eye(3), f, sensor, pixels)
    img = np.asarray(cast(o, d, scene))
    xs, ys = sensor_grid(f, sensor, pixels)
    for i, j in PIXELS_TO_CHECK:
        p = np.array([xs[j], ys[i], f]) * dist / f
        u = (p[0] - origin[0]) / tile[0]
        v = (p[1] - origin[1]) / tile[1]  # = -(p - o).(texture up) / tile
        want = np.asarray(color) * bilinear_by_hand(tex[1], u, v, True, True)
        np.testing.assert_allclose(img[i, j], want, rtol=2e-5, atol=2e-6)
    # The sampled coordinates span several repeats, so wrap-around was exercised.
    assert (xs[-1] - xs[0]) * dist / f / tile[0] > 3


def test_box_face_texture_is_clamped_bilinear_sample_computed_by_hand():
    f, sensor, pixels = CAM["focal"], CAM["sensor"], CAM["pixels"]
    tex = _textures(1)
    dist, half, color = 1.0, np.array([0.63, 0.47, 0.3]), (0.5, 1.0, 0.8)  # corners clamp
    scene = make_scene(boxes=[dict(pos=(0.02, -0.01, dist + half[2]), half=half, color=color,
                                   tex=0)], textures=tex)
    o, d = camera_rays(jnp.zeros(3), jnp.eye(3), f, sensor, pixels)
    img = np.asarray(cast(o, d, scene))
    xs, ys = sensor_grid(f, sensor, pixels)
    for i, j in PIXELS_TO_CHECK:
        p = np.array([xs[j], ys[i], f]) * dist / f - np.array([0.02, -0.01, dist + half[2]])
        assert np.all(np.abs(p[:2]) < half[:2]), "pixel must see the -z face"
        # -z face: texture up = local +y, right = up x normal = -x (documented convention).
        u = 0.5 * (1 - p[0] / half[0])
        v = 0.5 * (1 - p[1] / half[1])
        want = np.asarray(color) * bilinear_by_hand(tex[0], u, v, False, False)
        np.testing.assert_allclose(img[i, j], want, rtol=2e-5, atol=2e-6)


def test_sphere_texture_uses_spherical_angles_computed_by_hand():
    f, sensor, pixels = CAM["focal"], CAM["sensor"], CAM["pixels"]
    tex = _textures(2, (1, 6, 9, 3))
    centre, r = np.array([0.1, 0.05, 3.0]), 0.7
    srot = rot_from_seed(11)
    scene = make_scene(spheres=[dict(pos=centre, r=r, rot=srot, color=(1, 1, 1), tex=0)],
                       textures=tex)
    o, d = camera_rays(jnp.zeros(3), jnp.eye(3), f, sensor, pixels)
    img = np.asarray(cast(o, d, scene))
    xs, ys = sensor_grid(f, sensor, pixels)
    checked = 0
    for i, j in [(24, 32), (20, 28), (30, 36), (14, 40), (33, 25), (24, 45)]:
        dvec = np.array([xs[j], ys[i], f])
        dvec /= np.linalg.norm(dvec)
        b = dvec @ -centre
        disc = b * b - (centre @ centre - r * r)
        assert disc > 0
        q = srot.T @ (-(b + np.sqrt(disc)) * dvec - centre) / r
        u = 0.5 + np.arctan2(q[1], q[0]) / (2 * np.pi)
        v = np.arccos(np.clip(q[2], -1, 1)) / np.pi
        want = bilinear_by_hand(tex[0], u, v, True, False)
        np.testing.assert_allclose(img[i, j], want, rtol=1e-4, atol=1e-5)
        checked += 1
    assert checked == 6


# ----------------------------------------------------------------------------- projection


def test_project_points_matches_pixel_where_cast_sees_a_tiny_sphere():
    f, sensor, pixels = 0.0042, (0.0048, 0.0036), (1024, 768)  # 1024x768 onboard camera
    pos, rot = np.array([0.4, -0.3, 0.25]), rot_from_seed(5)
    pitch = sensor[0] / pixels[0]
    rng = np.random.default_rng(7)
    pc = np.column_stack([rng.uniform(-0.4, 0.4, 4), rng.uniform(-0.3, 0.3, 4),
                          rng.uniform(2.0, 5.0, 4)])
    pc[:, :2] *= pc[:, 2:3] * sensor[0] / f  # spread over the field of view
    points = pos + pc @ rot.T
    uv, front = project(jnp.asarray(pos, jnp.float32), jnp.asarray(rot, jnp.float32), f,
                        sensor, pixels, jnp.asarray(points, jnp.float32))
    assert np.all(np.asarray(front))
    o, d = camera_rays(jnp.asarray(pos, jnp.float32), jnp.asarray(rot, jnp.float32),
                       f, sensor, pixels)
    render = jax.jit(cast)
    for k in range(len(points)):
        r = 3.0 * pitch * pc[k, 2] / f  # ~3 px radius
        mask = hit_mask(render(o, d, make_scene(spheres=[dict(pos=points[k], r=r,
                                                              color=(1, 1, 1))])))
        ii, jj = np.nonzero(mask)
        assert 20 < len(ii) < 40
        np.testing.assert_allclose([jj.mean(), ii.mean()], np.asarray(uv[k]), atol=0.2)
        j, i = np.round(np.asarray(uv[k])).astype(int)
        assert mask[i, j]


def test_project_points_behind_camera_masked_with_finite_gradient():
    pts = jnp.array([[0.0, 0.0, -1.0], [0.1, 0.2, 0.0], [0.0, 0.1, 2.0]])
    uv, front = project(jnp.zeros(3), jnp.eye(3), 0.02, (0.036, 0.024), (36, 24), pts)
    np.testing.assert_array_equal(np.asarray(front), [False, False, True])
    # In front: (0, 0.1, 2) -> sensor y = 0.02 * 0.05 = 1 mm -> row 11.5 + 1 = 12.5.
    np.testing.assert_allclose(np.asarray(uv[2]), [17.5, 12.5], atol=1e-5)
    g = jax.grad(lambda p: project(jnp.zeros(3), jnp.eye(3), 0.02, (0.036, 0.024), (36, 24),
                                   p)[0].sum())(pts)
    assert np.all(np.isfinite(np.asarray(g)))


# ----------------------------------------------------------------------------- gradients


def _smooth_textures(shape):
    t, h, w = shape
    yy, xx = np.meshgrid(np.arange(h), np.arange(w), indexing="ij")
    out = []
    for k in range(t):
        base = [0.5 + 0.4 * np.sin(2 * np.pi * (xx / w + c / 3.0 + k / 5.0)) *
                np.cos(np.pi * (yy + 0.5) / h * (1 + c)) for c in range(3)]
        out.append(np.stack(base, axis=-1))
    return np.stack(out)


def _grad_scene(dtype, sphere_pos=(0.05, -0.02, 3.0), degenerate=False, inside=False):
    spheres = [dict(pos=sphere_pos, r=0.8, rot=rot_from_seed(1), color=(1, 0.9, 0.8), tex=0)]
    boxes = [dict(pos=(1.2, 0.3, 4.0), rot=rot_from_seed(2), half=(0.3, 0.4, 0.5),
                  color=(0.7, 1, 1), tex=1)]
    planes = [dict(pos=(0, 1.0, 0), rot=np.stack([[1, 0, 0], [0, 0, 1.0], [0, -1, 0]], 1),
                   tile=(0.5, 0.7), color=(1, 1, 1), tex=1)]
    if degenerate:
        # Pole of the sphere texture frame on the optical axis, a box with faces parallel to
        # the central row/column rays, a plane containing the camera centre (rays parallel).
        spheres[0]["rot"] = np.diag([1.0, -1.0, -1.0])
        spheres[0]["pos"] = (0, 0, 3.0)
        boxes.append(dict(pos=(1.0, 0, 6.0), half=(0.5, 0.5, 0.5), color=(1, 1, 1), tex=0))
        planes.append(dict(pos=(0, 0, 0), rot=np.stack([[0, 1, 0], [0, 0, 1.0], [1, 0, 0]], 1),
                           color=(1, 1, 1)))
    if inside:  # the camera inside a sphere sees its inner surface (pole on the axis too)
        spheres.append(dict(pos=(0, 0, 0), r=0.5, color=(1, 1, 1), tex=0))
    return make_scene(spheres, boxes, planes, textures=_smooth_textures((2, 16, 24)),
                      dtype=dtype)


@pytest.mark.parametrize("inside", [False, True])
def test_gradients_finite_everywhere_including_degenerate_rays(inside):
    pixels = (33, 25)  # odd: the central row/column rays are exactly axis-aligned
    o, d = camera_rays(jnp.zeros(3), jnp.eye(3), 0.03, (0.036, 0.027), pixels)
    scene = _grad_scene(jnp.float32, degenerate=True, inside=inside)

    def loss(scene, cam_pos, cam_rot):
        o, d = camera_rays(cam_pos, cam_rot, 0.03, (0.036, 0.027), pixels)
        return jnp.mean(cast(o, d, scene) ** 2)

    val, grads = jax.jit(jax.value_and_grad(loss, argnums=(0, 1, 2)))(
        scene, jnp.zeros(3), jnp.eye(3))
    assert np.isfinite(float(val))
    leaves = jax.tree_util.tree_leaves(grads)
    assert len(leaves) == 16
    for leaf in leaves:
        assert np.all(np.isfinite(np.asarray(leaf)))
    assert np.asarray(grads[1]).any()  # the camera position does influence the image
    ids = _ids(o, d, scene)
    if inside:
        assert hit_mask(cast(o, d, scene)).all()
    else:  # the degenerate geometry is in view: pole at the centre pixel, box on row 12
        np.testing.assert_array_equal(ids[12, 16], [1, 0, 0])
        assert np.any(np.all(ids[12] == [0, 1, 0], axis=-1))
        assert np.asarray(grads[0].box_pos).any() and np.asarray(grads[0].sphere_pos).any()


def _ids(o, d, scene):
    """Which geometry each pixel sees: render with unique flat colours, no textures."""
    flat = scene.replace(
        sphere_color=jnp.eye(3, dtype=o.dtype)[:1] * jnp.ones_like(scene.sphere_color),
        box_color=jnp.eye(3, dtype=o.dtype)[1:2] * jnp.ones_like(scene.box_color),
        plane_color=jnp.eye(3, dtype=o.dtype)[2:3] * jnp.ones_like(scene.plane_color),
        sphere_texture=(-1,) * len(scene.sphere_texture),
        box_texture=(-1,) * len(scene.box_texture),
        plane_texture=(-1,) * len(scene.plane_texture))
    return np.asarray(cast(o, d, flat))


def test_image_gradient_matches_float64_finite_differences():
    with x64():
        pixels = (48, 32)
        o, d = camera_rays(jnp.zeros(3, jnp.float64), jnp.eye(3, dtype=jnp.float64), 0.03,
                           (0.036, 0.024), pixels)
        base = jnp.array([0.05, -0.02, 3.0])

        def loss(sphere_pos, plane_pos):
            scene = _grad_scene(jnp.float64).replace(sphere_pos=sphere_pos[None],
                                                     plane_pos=plane_pos[None])
            return jnp.mean(cast(o, d, scene))

        plane0 = jnp.array([0.0, 1.0, 0.0])
        loss = jax.jit(loss)
        g_sphere, g_plane = jax.jit(jax.grad(loss, argnums=(0, 1)))(base, plane0)
        ids0 = _ids(o, d, _grad_scene(jnp.float64))
        assert len(np.unique(ids0.reshape(-1, 3), axis=0)) == 4  # sphere, box, plane, sky
        eps = 1e-6
        for arg, g in ((0, g_sphere), (1, g_plane)):
            fd = np.zeros(3)
            for k in range(3):
                step = np.zeros(3)
                step[k] = eps
                args_p = [base, plane0]
                args_m = [base, plane0]
                args_p[arg] = args_p[arg] + step
                args_m[arg] = args_m[arg] - step
                for a in (args_p, args_m):  # visibility unchanged by the perturbation
                    sc = _grad_scene(jnp.float64).replace(sphere_pos=a[0][None],
                                                          plane_pos=a[1][None])
                    np.testing.assert_array_equal(_ids(o, d, sc), ids0)
                fd[k] = (float(loss(*args_p)) - float(loss(*args_m))) / (2 * eps)
            g = np.asarray(g)
            assert np.abs(g).max() > 1e-4  # textured surfaces give non-zero derivatives
            np.testing.assert_allclose(g, fd, rtol=1e-4, atol=1e-7)


# ----------------------------------------------------------------------------- batching


def test_jit_and_vmap_over_camera_poses_match_single_renders():
    scene = _grad_scene(jnp.float32)
    cam_pos = jnp.array([[0.0, 0.0, 0.0], [0.3, -0.1, 0.2], [-0.2, 0.1, -0.5]])

    def one(p):
        o, d = camera_rays(p, jnp.eye(3), 0.03, (0.036, 0.024), (24, 16))
        return cast(o, d, scene)

    batched = jax.jit(jax.vmap(one))(cam_pos)
    one = jax.jit(one)
    assert batched.shape == (3, 16, 24, 3)
    for k in range(3):
        np.testing.assert_allclose(np.asarray(batched[k]), np.asarray(one(cam_pos[k])),
                                   rtol=1e-4, atol=1e-4)  # float32, far plane texels
    assert not np.allclose(np.asarray(batched[0]), np.asarray(batched[1]))


# ----------------------------------------------------------------------------- engine


def _engine_scene():
    from thesis.physics import Builder

    b = Builder("camera_test", dt=0.01)
    b.add_texture("smooth", _smooth_textures((1, 8, 12))[0])
    b.add_sphere("ball", 0.3, pos=(0.0, 0.0, 1.0), color=(1.0, 0.2, 0.2), texture="smooth")
    b.add_box("crate", size=(0.4, 0.6, 0.2), pos=(0.8, 0.3, 0.5), rot=rot_from_seed(4),
              color=(0.2, 1.0, 0.2), texture="smooth")
    b.add_plane("ground", (0, 0, 1), 0.0, color=(0.6, 0.6, 0.6), texture="smooth")
    front = np.stack([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]], axis=1)  # looks along +y
    b.add_camera("front", "world", pos=(0.2, -4.0, 0.8), rot=front, focal_length=0.018,
                 sensor_size=(0.036, 0.012), pixels=(96, 32))
    b.add_camera("onboard", "crate", pos=(0.0, -0.3, 0.1), rot=front, focal_length=0.0042,
                 sensor_size=(0.0048, 0.0036), pixels=(128, 96))
    return b.build()


def _moved(state):
    """A state with the ball and the crate moved to other poses."""
    pos = np.asarray(state.pos).copy()
    pos[0] += (0.2, -0.1, 0.15)
    pos[1] += (-0.3, 0.2, 0.1)
    rot = np.stack([rot_from_seed(8), rot_from_seed(9)])
    return state.replace(pos=jnp.asarray(pos, jnp.float32), rot=jnp.asarray(rot, jnp.float32))


def test_render_reads_model_and_state_like_a_hand_built_scene():
    from thesis.physics import render

    from thesis.physics.camera import camera_pose, project_points

    model, state = _engine_scene()
    state = _moved(state)
    p, r = np.asarray(state.pos, np.float64), np.asarray(state.rot, np.float64)
    plane = int(np.nonzero(np.asarray(model.geom_type) == 2)[0][0])
    tex = np.asarray(model.textures)
    scene = make_scene(
        spheres=[dict(pos=p[0], r=0.3, rot=r[0], color=(1.0, 0.2, 0.2), tex=0)],
        boxes=[dict(pos=p[1], rot=r[1], half=(0.2, 0.3, 0.1), color=(0.2, 1.0, 0.2), tex=0)],
        planes=[dict(pos=(0, 0, 0), rot=np.asarray(model.geom_rot[plane]), tile=(1.0, 1.0),
                     color=(0.6, 0.6, 0.6), tex=0)],
        textures=tex, background=(0.0, 191 / 255, 1.0))
    assert np.allclose(np.asarray(model.geom_rot[plane])[:, 2], [0, 0, 1])
    front = np.stack([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]], axis=1)
    cams = {
        "front": (np.array([0.2, -4.0, 0.8]), front, 0.018, (0.036, 0.012), (96, 32)),
        "onboard": (p[1] + r[1] @ [0.0, -0.3, 0.1], r[1] @ front, 0.0042, (0.0048, 0.0036),
                    (128, 96)),
    }
    ball = jnp.asarray(p[:1], jnp.float32)
    for name, (cpos, crot, f, sensor, pixels) in cams.items():
        got = np.asarray(jax.jit(render, static_argnums=2)(model, state, name))
        o, d = camera_rays(jnp.asarray(cpos, jnp.float32), jnp.asarray(crot, jnp.float32),
                           f, sensor, pixels)
        want = np.asarray(cast(o, d, scene))
        assert got.shape == (pixels[1], pixels[0], 3)
        # float32: the camera pose composed on device vs. in float64 here differs by ~1e-7,
        # which moves the texel seen near the horizon of the infinite ground plane (hits
        # hundreds of metres away) and can flip a silhouette pixel; allow 0.5 % of pixels.
        bad = np.any(np.abs(got - want) > 1e-4, axis=-1)
        assert bad.mean() < 0.005, bad.mean()
        np.testing.assert_allclose(got.mean(axis=(0, 1)), want.mean(axis=(0, 1)), atol=2e-4)
        assert len(np.unique(np.round(got.reshape(-1, 3), 3), axis=0)) > 50  # textured
        wpos, wrot = camera_pose(model, state, name)
        np.testing.assert_allclose(np.asarray(wpos), cpos, atol=1e-5)
        np.testing.assert_allclose(np.asarray(wrot), crot, atol=1e-5)
        uv, front_mask = project_points(model, state, name, ball)
        uv_ref, front_ref = project(cpos, crot, f, sensor, pixels, p[:1])
        np.testing.assert_allclose(np.asarray(uv), np.asarray(uv_ref), rtol=1e-5, atol=1e-3)
        assert bool(front_mask[0]) == bool(front_ref[0]) == bool((p[0] - cpos) @ crot[:, 2] > 0)
    assert bool(project_points(model, state, "front", ball)[1][0])


def test_render_batch_after_engine_steps_tracks_the_falling_ball():
    from thesis.physics import step

    from thesis.physics.camera import project_points, render_batch

    model, state = _engine_scene()
    states = [state]
    jstep = jax.jit(step)
    with jax.numpy_rank_promotion("allow"):  # the engine's step is not rank-strict (yet)
        for _ in range(30):  # the ball falls under gravity (0.3 s)
            states.append(jstep(model, states[-1], jnp.zeros((0,), jnp.float32)))
    batch = jax.tree_util.tree_map(lambda *xs: jnp.stack(xs), *states[::10])
    flat = model.replace(textures=jnp.ones_like(model.textures))  # flat colours: find the ball
    images = np.asarray(render_batch(flat, batch, "front"))
    assert images.shape == (4, 32, 96, 3)
    rows = []
    for k, s in enumerate(states[::10]):
        ball = np.all(np.abs(images[k] - np.array([1.0, 0.2, 0.2], np.float32)) < 1e-6, axis=-1)
        ii, jj = np.nonzero(ball)
        assert len(ii) > 10
        uv, front = project_points(flat, s, "front", s.pos[:1])
        assert bool(front[0])
        np.testing.assert_allclose([jj.mean(), ii.mean()], np.asarray(uv[0]), atol=0.35)
        rows.append(ii.mean())
    assert np.all(np.diff(rows) > 0)  # it moves down the image as it falls


def test_render_gradient_wrt_state_is_finite_and_nonzero():
    from thesis.physics import render

    model, state = _engine_scene()

    def loss(pos, rot):
        return jnp.mean(render(model, state.replace(pos=pos, rot=rot), "onboard"))

    g_pos, g_rot = jax.jit(jax.grad(loss, argnums=(0, 1)))(state.pos, state.rot)
    assert np.all(np.isfinite(np.asarray(g_pos))) and np.all(np.isfinite(np.asarray(g_rot)))
    assert np.abs(np.asarray(g_pos[1])).max() > 0  # the onboard camera rides on the crate
