# Sphinx configuration of the spectralize user guide (`make docs`: HTML into build/docs/html).
# The build copies docs/ into the build tree, adds the flag chapter that `spectralize
# --help-markdown` prints from the settings schema, and imports the built Python module for
# the API reference (PYTHONPATH set by the build).
project = "spectralize"
author = "the spectralize authors"
copyright = "the spectralize authors"
extensions = ["myst_parser", "sphinx.ext.autodoc"]
source_suffix = {".md": "markdown"}
myst_enable_extensions = ["deflist"]
myst_heading_anchors = 4  # links to sections by their GitHub-style slugs (file.md#section)
exclude_patterns = ["snippets", "conf.py", "guide/flags/*"]  # flags/: included by chapters
html_theme = "sphinx_rtd_theme"
html_title = "spectralize user guide"
html_show_sourcelink = False
smartquotes = False  # flags keep their two hyphens
autodoc_member_order = "bysource"


def _as_printed(app, what, name, obj, options, lines):
    """The module's docstrings are plain text (what help() prints): shown as such, verbatim."""
    if lines:
        lines[:] = ["::", ""] + ["   " + line for line in lines] + [""]


def setup(app):
    app.connect("autodoc-process-docstring", _as_printed)
