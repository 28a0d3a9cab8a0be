"""The Q distance of a hand-written grasp, its gradients, and one gradient step that improves it.

Four fingertip contacts on a sphere of radius 40 mm (a thumb and three fingers bunched on the
other side), normals pointing into the sphere, friction coefficient 0.3. The script prints the
Q distance (< 0: force closure; more negative: a larger margin, about -0.1 is a good grasp) and
its gradients with respect to the contact points and normals, checks one entry against a finite
difference, then moves every contact a few millimetres over the sphere against the gradient and
shows that Q decreases. On a sphere a contact's normal follows its point (``n = -p / r``), so the
step uses the total derivative ``dQ/dp + (dn/dp)^T dQ/dn``. The torque reference point (the
centre) and the torque scale are held fixed, as the gradients assume.

Writes ``grasp_quality.png`` (Q along the step direction) into ``--out``.

Usage::

    python examples/grasp_quality.py [--out DIR]      # default ./examples-out
"""

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder  # noqa: E402

RADIUS = 40.0  # mm
MU = 0.3


def on_sphere(azimuth_deg, elevation_deg):
    """Contact points (mm) on the sphere and their normals, pointing into it (towards the centre)."""
    az, el = np.radians(azimuth_deg), np.radians(elevation_deg)
    points = RADIUS * np.c_[np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)]
    return points, -points / RADIUS


def quality(points):
    """Q distance of contacts at ``points`` on the sphere, centre and torque scale held fixed."""
    return sg.q_distance(points, -points / np.linalg.norm(points, axis=1, keepdims=True), mu=MU,
                         center=np.zeros(3), torque_scale=RADIUS)


def total_gradient(points, q):
    """dQ/dp of contacts that stay on the sphere: the normal n = -p/|p| moves with the point."""
    n = -points / RADIUS
    tangent = np.eye(3) - n[:, :, None] * n[:, None, :]                 # (c, 3, 3), I - n n^T
    grad = q.grad_points - np.einsum("cab,cb->ca", tangent, q.grad_normals) / RADIUS
    return np.einsum("cab,cb->ca", tangent, grad)                       # along the surface only


def project(points):
    """Back onto the sphere."""
    return RADIUS * points / np.linalg.norm(points, axis=1, keepdims=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=output_folder, default="examples-out", help="output folder (default ./examples-out)")
    args = parser.parse_args(argv)
    out = args.out

    # a thumb at azimuth 0 and three fingers bunched together on the far side
    points, normals = on_sphere([0.0, 146.0, 186.0, 189.0], [-22.0, -17.0, -10.0, 4.0])
    q = sg.q_distance(points, normals, mu=MU, center=np.zeros(3), torque_scale=RADIUS)
    print(f"Q distance = {q.value:+.5f} ({'force closure' if q.force_closure else 'no force closure'}, "
          f"{q.kind}, degenerate: {q.degenerate})")
    # a zero row (contact 2 here): its wrenches have zero weight in the LP's optimum, so moving
    # that contact a little does not change Q. `degenerate` would flag a grasp where the derivative does not
    # exist (ties in the LP); the gradients are then a valid one-sided choice.
    print("dQ/dp (per mm):\n", np.array2string(q.grad_points, precision=5, suppress_small=True))
    print("dQ/dn:\n", np.array2string(q.grad_normals, precision=5, suppress_small=True))

    # the LP-dual gradient against a central finite difference, contact 1, coordinate y
    h = 1e-4
    shift = np.zeros_like(points)
    shift[1, 1] = h
    fd = (sg.q_distance(points + shift, normals, mu=MU, center=np.zeros(3), torque_scale=RADIUS).value
          - sg.q_distance(points - shift, normals, mu=MU, center=np.zeros(3), torque_scale=RADIUS).value) / (2 * h)
    print(f"dQ/dp[1, y]: dual {q.grad_points[1, 1]:+.6f}, finite difference {fd:+.6f}")

    # one step against the total gradient, scaled so that no coordinate moves more than 5 mm
    g = total_gradient(points, q)
    direction = -g / np.abs(g).max()
    steps = np.linspace(0.0, 8.0, 33)
    values = [quality(project(points + s * direction)).value for s in steps]
    step = 5.0
    q_new = quality(project(points + step * direction))
    print(f"after a {step:g} mm gradient step: Q = {q_new.value:+.5f} (was {q.value:+.5f}), "
          f"{'improved' if q_new.value < q.value else 'not improved'}")

    fig, ax = plt.subplots(figsize=(5.5, 3.5))
    ax.plot(steps, values, color="tab:blue", label="Q along -grad (contacts kept on the sphere)")
    ax.plot(steps, q.value + steps * (g * direction).sum(), "--", color="tab:red", label="first-order prediction")
    ax.axvline(step, color="gray", lw=0.8)
    ax.set_xlabel("step (mm, largest coordinate move)")
    ax.set_ylabel("Q distance")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "grasp_quality.png", dpi=110)
    plt.close(fig)
    print(f"wrote {out / 'grasp_quality.png'}")


if __name__ == "__main__":
    main()
