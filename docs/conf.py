"""Sphinx configuration of the railgrowth documentation site.

Build it (CI does, with warnings as errors) from the repository root:

    python -m sphinx -W --keep-going -b html docs docs/_build/html

Pages: every ``docs/*.md`` (MyST markdown, formulas by MathJax), picked up by a glob in the
index; the API reference is generated from the numpydoc docstrings of every module of ``rail``
(``docs/reference/api.rst``, autosummary; its stubs are written to ``docs/reference/api/`` at
build time and not committed); the gallery shows
the figure baselines of ``tests/baselines/figures`` with the HTML report's captions
(``workflow/report/figNN.rst``) rendered for ``config/config.yaml``. Nothing here runs the workflow.
"""

import sys
from pathlib import Path

import jinja2
import yaml

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))  # document this checkout's rail/, not an installed copy

import rail  # noqa: E402

project = "railgrowth"
author = "railgrowth contributors"
copyright = "railgrowth contributors"
release = version = rail.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]

# MyST: $...$ and $$...$$ formulas (docs/track.md) rendered by MathJax; anchors on the headings
# so that pages can link to a section.
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3

# API reference: one page per module, everything public that the module defines (not only its
# __all__: tests/test_docs.py checks every public name), in source order.
autosummary_generate = True
autosummary_ignore_module_all = True
autodoc_member_order = "bysource"
autodoc_default_options = {"members": True, "ignore-module-all": True}
# numpydoc parses the docstrings; the members are listed by autodoc already, so no extra
# per-class member tables (they would point at stub pages that do not exist).
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

html_theme = "alabaster"
html_title = "railgrowth"
html_static_path = []
html_theme_options = {"description": "rail roughness growth on tangent track", "page_width": "1100px"}


# --- the figure gallery -----------------------------------------------------------------------
# docs/reference/gallery.rst holds the marker line below; at build time it is replaced by one figure per
# baseline image with the HTML report's caption (a Jinja template over snakemake.config),
# rendered for the default configuration. Images and captions stay where the workflow keeps
# them, so the gallery can never show a figure the regression does not check.
GALLERY_MARKER = ".. railgrowth-gallery::"
FIGURES = ROOT / "tests" / "baselines" / "figures"
CAPTIONS = ROOT / "workflow" / "report"


class _Snakemake:
    def __init__(self, config):
        self.config = config


def gallery_rst() -> str:
    """reStructuredText of every baseline figure with its rendered report caption."""
    config = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())
    env = jinja2.Environment(undefined=jinja2.StrictUndefined)
    out = []
    for png in sorted(FIGURES.glob("fig*.png")):
        caption_file = CAPTIONS / f"{png.stem}.rst"
        if not caption_file.exists():
            raise FileNotFoundError(f"no report caption {caption_file} for the baseline figure {png}")
        caption = env.from_string(caption_file.read_text()).render(snakemake=_Snakemake(config))
        number = int(png.stem[3:])
        out += [f".. _gallery-fig{number:02d}:", "",
                f".. figure:: ../../tests/baselines/figures/{png.name}",
                f"   :alt: Fig. {number}", "   :width: 100%", ""]
        out += ["   " + line if line.strip() else "" for line in caption.strip().splitlines()]
        out.append("")
    return "\n".join(out)


def _fill_gallery(app, docname, source):
    if GALLERY_MARKER in source[0]:
        source[0] = source[0].replace(GALLERY_MARKER, gallery_rst())


def setup(app):
    app.connect("source-read", _fill_gallery)
