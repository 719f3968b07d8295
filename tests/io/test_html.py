"""The HTML export: one page that loads nothing, whose swim decodes back to the data, and
that Chromium draws, with the creature where its links are, frame by frame."""

import dataclasses
import json
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from aquagait.io.export import ExportUnavailable, export_swim, html

CHROMIUM = Path("/usr/bin/chromium")
FLAGS = ["--enable-unsafe-swiftshader"]
"""Chromium draws WebGL on SwiftShader (CPU) where there is no GPU; it falls back to it
without the flag too, for now, with a warning that the fallback needs this opt-in."""
VIEWPORT = {"width": 640, "height": 480}


class _Page(HTMLParser):
    """Every tag's attributes, and the text of each script and style element."""

    def __init__(self, text):
        super().__init__()
        self.tags, self.scripts, self.styles, self._into = [], [], [], None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        self._into = {"script": self.scripts, "style": self.styles}.get(tag)
        if self._into is not None:
            self._into.append((dict(attrs), ""))

    def handle_data(self, data):
        if self._into is not None:
            attrs, text = self._into[-1]
            self._into[-1] = (attrs, text + data)

    def handle_endtag(self, tag):
        self._into = None


def _swim(path):
    scripts = _Page(path.read_text(encoding="utf-8")).scripts
    (text,) = [text for attrs, text in scripts if attrs.get("id") == "aquagait-swim"]
    return json.loads(text)


def _traces(swim):
    """Traces (F, N, L, 3) and opacity (F, N, L) rebuilt from the page's JSON as
    html.py's docstring describes it (not with the writer's own code)."""
    t = swim["traces"]
    points, size = html.decode(t["points"]), html.decode(t["size"]).astype(int)
    count, length = t["count"], t["length"]
    frames = size.shape[0]
    last = html.decode(t["last"]) if "last" in t else np.arange(frames * count).reshape(size.shape)
    k = np.arange(length)
    kept = k >= length - size[..., None]  # position k is one of the trace's newest `size`
    index = last[..., None].astype(int) - (length - 1 - k) * t["stride"]
    traces = np.full((*size.shape, length, 3), np.nan, np.float32)
    traces[kept] = points[index[kept]]
    alpha = np.zeros(size.shape + (length,))
    position = np.nonzero(kept)[-1]
    alpha[kept] = html.decode(t["alpha"])[index[kept]] / 255 * html.decode(t["fade"])[position]
    return traces, alpha


def _young_as_nan(traces):
    """Traces with each position that has a NaN all NaN (in 2D, z is 0 where x and y are NaN)."""
    return np.where(np.isnan(traces).any(axis=-1, keepdims=True), np.float32(np.nan), traces)


def test_the_page_is_one_file_that_loads_nothing(eel_export, tmp_path):
    _, data = eel_export
    path = export_swim(data, "html", tmp_path / "swim.html")
    page = _Page(path.read_text(encoding="utf-8"))
    assert [tag for tag, _ in page.tags][:1] == ["html"]
    links = [(tag, a) for tag, attrs in page.tags for a in attrs if a in ("src", "href")]
    assert links == []  # no script, style sheet, image or module from elsewhere
    kinds = [attrs.get("type") for attrs, _ in page.scripts]
    assert kinds == ["application/json", None]  # the swim, then the viewer: no modules
    viewer = page.scripts[1][1]
    assert re.search(r"\bimport\b", viewer) is None and len(viewer) > 100_000  # three.js inlined
    assert all("url(" not in text and "@import" not in text for _, text in page.styles)
    ids = {attrs.get("id") for _, attrs in page.tags}
    assert {"scrub", "play", "traces", "info"} <= ids


def test_the_embedded_swim_decodes_back_to_the_data(eel_export, fish_export, tmp_path):
    for _, data in (eel_export, fish_export):
        swim = _swim(export_swim(data, "html", tmp_path / f"{data.name}.html"))
        assert (swim["name"], swim["frames"], swim["fps"]) == (data.name, data.frames, data.fps)
        for field in ("time", "link_pos", "link_quat"):
            np.testing.assert_array_equal(
                html.decode(swim[field]), getattr(data, field).astype("f4")
            )
        for link, mesh, name in zip(swim["links"], data.meshes, data.link_names, strict=True):
            assert link["name"] == name
            np.testing.assert_array_equal(html.decode(link["vertices"]), mesh.vertices.astype("f4"))
            np.testing.assert_array_equal(html.decode(link["triangles"]), mesh.triangles)
            assert np.abs(html.decode(link["colours"]) / 255 - mesh.colours).max() <= 0.5 / 255
        traces, alpha = _traces(swim)
        np.testing.assert_array_equal(traces, _young_as_nan(data.traces))
        shown = ~np.isnan(traces[..., 0])  # a NaN position's opacity is not kept
        assert np.abs(alpha - data.trace_alpha)[shown].max() <= 1 / 255
        # a trace is its particle's last positions: each stored once a frame, not L times
        count = data.traces.shape[1]
        assert swim["traces"]["stride"] == count and "last" not in swim["traces"]
        assert html.decode(swim["traces"]["points"]).shape == (data.frames * count, 3)


def _reversed_every_other_frame(data):
    traces, alpha = data.traces.copy(), data.trace_alpha.copy()
    traces[1::2], alpha[1::2] = traces[1::2, ::-1], alpha[1::2, ::-1]
    return dataclasses.replace(data, traces=traces, trace_alpha=alpha)


def _random_opacity(data):
    alpha = np.random.default_rng(0).random(data.trace_alpha.shape, np.float32)
    return dataclasses.replace(data, trace_alpha=alpha)


@pytest.mark.parametrize("change", [_reversed_every_other_frame, _random_opacity])
def test_traces_that_are_not_particle_histories_are_written_as_they_are(
    change, eel_export, tmp_path
):
    data = change(eel_export[1])
    swim = _swim(export_swim(data, "html", tmp_path / "swim.html"))
    assert swim["traces"]["stride"] == 1 and "last" in swim["traces"]
    traces, alpha = _traces(swim)
    np.testing.assert_array_equal(traces, _young_as_nan(data.traces))
    shown = ~np.isnan(traces[..., 0])
    assert np.abs(alpha - data.trace_alpha)[shown].max() <= 0.5 / 255 + 1e-6


def test_a_missing_viewer_says_how_to_build_it(eel_export, tmp_path, monkeypatch):
    monkeypatch.setattr(html, "VIEWER", "not-built.js")
    with pytest.raises(ExportUnavailable, match="tools/build_viewer.sh"):
        export_swim(eel_export[1], "html", tmp_path / "swim.html")
    assert not any(tmp_path.iterdir())


# In Chromium ---------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def browser():
    sync_api = pytest.importorskip("playwright.sync_api")
    if not CHROMIUM.exists():
        pytest.skip(f"no Debian chromium at {CHROMIUM} (apt-get install chromium)")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=FLAGS)
        yield browser
        browser.close()


@pytest.fixture
def open_swim(browser, tmp_path):
    """Open a swim's page; after the test, no errors may have been logged."""
    pages, errors = [], []

    def open_(data):
        path = export_swim(data, "html", tmp_path / f"{data.name}.html")
        page = browser.new_page(viewport=VIEWPORT)
        pages.append(page)
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda err: errors.append(str(err)))
        page.goto(path.as_uri())
        page.wait_for_function("window.aquagait && window.aquagait.ready", timeout=20_000)
        return page

    yield open_
    for page in pages:
        page.close()
    assert errors == []


def _drawn(page) -> np.ndarray:
    """(H, W) True where the picture is not the white background."""
    import imageio.v3 as iio

    image = iio.imread(page.screenshot(), extension=".png")[..., :3].astype(int)
    return (255 - image).max(axis=-1) > 24


def _project(page, points) -> np.ndarray:
    js = "ps => ps.map(p => window.aquagait.project(p[0], p[1], p[2]))"
    return np.array(page.evaluate(js, np.asarray(points, float).tolist()))


def test_the_page_plays_and_scrubs_in_chromium(eel_export, open_swim):
    _, data = eel_export
    page = open_swim(data)
    assert page.evaluate("[window.aquagait.frames, window.aquagait.frame]") == [data.frames, 0]
    page.click("#play")
    page.wait_for_function("window.aquagait.frame > 0", timeout=5_000)
    page.click("#play")  # pause
    assert page.inner_text("#play") == "Play"
    page.locator("#scrub").fill("5")
    assert page.evaluate("window.aquagait.frame") == 5
    assert f"t = {data.time[5]:.2f} s" in page.inner_text("#info") and "frame 5" in page.inner_text(
        "#info"
    )
    page.evaluate("window.aquagait.setFrame(1e9)")  # clamped to the last frame
    assert page.locator("#scrub").input_value() == str(data.frames - 1)


@pytest.mark.parametrize("swim", ["eel_export", "fish_export"])
def test_the_creature_is_drawn_where_its_links_are_at_every_frame_shown(swim, open_swim, request):
    _, data = request.getfixturevalue(swim)
    page = open_swim(data)
    page.uncheck("#traces")
    page.add_style_tag(content="#info, #bar { visibility: hidden; }")
    masks = []
    for frame in (0, data.frames - 1):
        page.evaluate(f"window.aquagait.setFrame({frame})")
        drawn = _drawn(page)
        grown = drawn.copy()  # a link origin on the silhouette's edge counts, within 2 px
        for axis in (0, 1):
            for shift in (-2, -1, 1, 2):
                grown |= np.roll(drawn, shift, axis=axis)
        x, y = _project(page, data.link_pos[frame]).T
        assert grown[np.round(y).astype(int), np.round(x).astype(int)].all(), (frame, x, y)
        masks.append(drawn)
    assert (masks[0] != masks[1]).sum() > 20  # it moved
    root = data.link_pos[0, 0]
    (_, below), (_, above) = _project(page, [root, root + [0, 0, 0.01]])
    assert above < below  # +z is up on the screen


def test_the_traces_are_drawn_over_the_water(eel_export, open_swim):
    _, data = eel_export
    page = open_swim(data)
    page.add_style_tag(content="#info, #bar { visibility: hidden; }")
    page.evaluate(f"window.aquagait.setFrame({data.frames - 1})")
    with_traces = _drawn(page)
    page.evaluate("document.getElementById('traces').click()")  # hidden, not for page.uncheck
    assert (with_traces & ~_drawn(page)).sum() > 50
