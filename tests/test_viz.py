"""Figures: the grasp gallery's layout and its bad input."""

import matplotlib.image as mpimg
import pytest
import trimesh

import synergrasp as sg
from synergrasp import viz


@pytest.fixture(scope="module")
def short_plan():
    obj = sg.objects.ellipsoid()
    return sg.plan(obj, "precision", max_iter=2, restarts=1), obj


def test_gallery_grid(tmp_path, short_plan):
    result, obj = short_plan
    hand = sg.SynergyHand.default()
    image = mpimg.imread(viz.plot_grasps([(result, obj, f"view {i}") for i in range(5)], hand, tmp_path / "g.png", columns=3))
    height, width = image.shape[:2]
    assert width == pytest.approx(3 * 2.6 * 110, abs=2) and height == pytest.approx(2 * 2.6 * 110, abs=2)


def test_gallery_needs_a_plan(tmp_path):
    with pytest.raises(ValueError, match="at least one"):
        viz.plot_grasps([], sg.SynergyHand.default(), tmp_path / "g.png")


def test_poses_figure_explains_its_colours(tmp_path, short_plan, monkeypatch):
    """The finger colours, the palm and the contacts are named in a legend."""
    result, obj = short_plan
    figures = []
    monkeypatch.setattr(viz, "_save", lambda fig, path, dpi: figures.append(fig) or path)
    viz.plot_poses(result, obj, sg.SynergyHand.default(), tmp_path / "poses.png")
    legend = figures[0].axes[0].get_legend()
    names = [text.get_text() for text in legend.get_texts()]
    assert names[:6] == ["thumb", "index", "middle", "ring", "little", "palm"]
    colours = [handle.get_color() for handle in legend.legend_handles[:5]]
    assert colours == ["tab:red", "tab:orange", "tab:green", "tab:purple", "tab:brown"]
    assert ("contacts" in names) == bool(len(result.contact_points))


def test_a_mesh_of_many_faces_is_drawn_as_its_convex_pieces(monkeypatch):
    """matplotlib draws every face in every frame of the reach's GIF: beyond DRAW_FACES, the pieces are drawn."""
    import matplotlib.pyplot as plt

    obj = sg.objects.from_mesh(trimesh.creation.icosphere(subdivisions=4, radius=40.0), cache=False)  # 5120 faces
    pieces = sum(len(p.facets) for p in obj.convex)
    drawn, original = [], viz.Poly3DCollection

    def collection(verts, **kwargs):
        drawn.append(len(verts))
        return original(verts, **kwargs)

    monkeypatch.setattr(viz, "Poly3DCollection", collection)
    for limit in (len(obj.mesh.faces), len(obj.mesh.faces) - 1):
        monkeypatch.setattr(viz, "DRAW_FACES", limit)
        fig = plt.figure()
        viz._draw_object(fig.add_subplot(projection="3d"), obj)
        plt.close(fig)
    assert drawn == [len(obj.mesh.faces), pieces] and pieces < len(obj.mesh.faces)


def test_labels_and_plans_given_as_generators_are_drawn(tmp_path, short_plan):
    """A generator of labels drew no cP curve (the check read it through before the figure did); a generator of
    plans for the gallery raised "has no len()"."""
    result, obj = short_plan
    labels = ["T0", "I0", "M0"]
    listed = viz.status_figure(result, labels=labels)
    generated = viz.status_figure(result, labels=(name for name in labels))
    assert [len(ax.get_lines()) for ax in generated.axes] == [len(ax.get_lines()) for ax in listed.axes]
    assert [t.get_text() for t in generated.axes[0].get_legend().get_texts()][:3] == [f"$g_{{{n}}}$" for n in labels]
    hand = sg.SynergyHand.default()
    assert viz.plot_grasps(((result, obj, f"view {i}") for i in range(2)), hand, tmp_path / "g.png").is_file()


def test_status_rows_of_renamed_fingers_get_their_fingers_colours(short_plan):
    """Colours keyed on the paper hand's finger letters: a hand whose fingers are named otherwise drew every row
    grey and solid. Now the fingers take the poses figure's colours in their order, the phalanges its line styles."""
    import matplotlib.colors as mcolors
    import matplotlib.pyplot as plt

    result, _ = short_plan
    paper, renamed = ["T0", "I0", "M0", "R0", "L0"], ["thumb0", "index0", "middle0", "ring0", "little0"]
    numbered = ["f10", "f20", "f30", "f40", "f50"]  # fingers f1 ... f5: the phalanx is the label's last digit
    colours = []
    for labels in (paper, renamed, numbered):
        fig = viz.status_figure(result, labels=labels)
        colours.append([mcolors.to_hex(line.get_color()) for line in fig.axes[0].get_lines()[:5]])
        plt.close(fig)
    assert colours[0] == colours[1] == colours[2] and len(set(colours[1])) == 5
    assert viz._finger_and_phalanx("index finger2") == ("index finger", 2) and viz._finger_and_phalanx("P") == ("P", None)
    assert viz._finger_and_phalanx("f12") == ("f1", 2)
