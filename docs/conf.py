# Sphinx configuration of the linkfit user guide (scripts/docs.sh builds it into build/docs/html).
# The pages are MyST Markdown; the API page is generated from the docstrings of the Python module
# in the build tree (scripts/docs.sh puts <build>/python first on PYTHONPATH).
import linkfit

project = "linkfit"
author = "the linkfit authors"
copyright = "the linkfit authors"
# The project's one version (CMakeLists.txt), as `linkfit --version` prints it.
release = linkfit.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
]
source_suffix = {".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build"]

# Equations as $...$, $$...$$ and amsmath environments; links to headings as page.md#slug.
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3

# The docstrings are Google style (Args:, Returns:, Raises:, Example:).
napoleon_google_docstring = True
napoleon_numpy_docstring = False
autodoc_member_order = "bysource"
# Types named in the docstrings that have no page here: builtins and other libraries.
nitpick_ignore_regex = [
    ("py:class", r"(int|str|dict|list|float|bool|None|optional)"),
    ("py:class", r"(list|dict|str|int) (of|or) .*"),
    ("py:class", r".* or None"),
    ("py:class", r"(dask|matplotlib|numpy|distributed)\..*"),
]

html_theme = "alabaster"
html_title = "linkfit " + release
html_theme_options = {
    "description": "kinematic synthesis of linkages",
    "fixed_sidebar": True,
}
