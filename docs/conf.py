# Sphinx configuration of the linkfit user guide (scripts/docs.sh builds it into build/docs/html).
# The pages are MyST Markdown; the API page is generated from the docstrings of the Python module
# in the build tree (scripts/docs.sh puts <build>/python first on PYTHONPATH).
import os

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

# Equations: MathJax from Debian's libjs-mathjax (scripts/setup.sh installs it), so that the guide
# in build/docs/html shows them offline; LINKFIT_MATHJAX names another copy (a URL) for a guide
# served elsewhere; without either, Sphinx's default (MathJax from its CDN).
_debian_mathjax = "/usr/share/javascript/mathjax/MathJax.js"
if os.environ.get("LINKFIT_MATHJAX"):
    mathjax_path = os.environ["LINKFIT_MATHJAX"]
elif os.path.exists(_debian_mathjax):
    # MathJax 2: MyST's settings are MathJax 3's, so the classes it marks are said here.
    mathjax_path = "file://" + _debian_mathjax + "?config=TeX-AMS-MML_HTMLorMML"
    myst_update_mathjax = False
    mathjax2_config = {"tex2jax": {"processClass": "tex2jax_process|mathjax_process|math",
                                   "ignoreClass": "tex2jax_ignore|mathjax_ignore"}}

html_theme = "alabaster"
html_title = "linkfit " + release
html_theme_options = {
    "description": "kinematic synthesis of linkages",
    "fixed_sidebar": True,
    "page_width": "1160px",  # the benchmark tables and code listings are wide
    "sidebar_width": "230px",
}
