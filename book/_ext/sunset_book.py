"""Sphinx helpers for the sunset book: numbers in ×10ⁿ notation, a quiet log.

Chapters glue numbers with format specs such as ``{glue:text}`err:.1e```,
which Python writes as ``6.7e-06``. A reader expects ``6.7 × 10⁻⁶``.
``numbers_sci.scientific`` rewrites one number, and the ``doctree-resolved`` handler
rewrites every such number in the prose of a page (never in code, math or raw
output), so a chapter keeps its ordinary format specs.

myst-parser and myst-nb print their whole configuration objects when a build
starts; a filter on Sphinx's log handlers drops those two lines (and nothing
else), so that what the build log says is news.

Registered in ``_config.yml`` under ``sphinx: local_extensions``.
"""

from __future__ import annotations

import logging
import re

from docutils import nodes

from numbers_sci import scientific

#: Nodes whose text is code, mathematics or raw output: left as they are.
_SKIP = (nodes.literal, nodes.literal_block, nodes.math, nodes.math_block, nodes.raw,
         nodes.FixedTextElement)


def _skipped(node: nodes.Node) -> bool:
    parent = node.parent
    while parent is not None:
        if isinstance(parent, _SKIP):
            return True
        parent = parent.parent
    return False


def rewrite_numbers(app, doctree: nodes.document, docname: str) -> None:
    """Rewrite e-notation numbers in the prose of a resolved page."""
    for text in list(doctree.findall(nodes.Text)):
        old = str(text)
        if "e" not in old and "E" not in old:
            continue
        new = scientific(old)
        if new != old and not _skipped(text):
            text.parent.replace(text, nodes.Text(new))


#: The configuration dumps: "myst v3.0.1: MdParserConfig(...)", "myst-nb v1.4.0: NbParserConfig(...)".
CONFIG_DUMP = re.compile(r"\b(MdParserConfig|NbParserConfig)\(")


class NoConfigDump(logging.Filter):
    """Drop the parsers' configuration dumps from Sphinx's log."""

    def filter(self, record: logging.LogRecord) -> bool:
        try:
            text = record.getMessage()
        except (TypeError, ValueError):
            text = str(record.msg)
        return not CONFIG_DUMP.search(text)


def unnumber_front_matter(app, env) -> list[str]:
    """Figures of pages outside the numbered chapters (the intro's picture) get no number.

    Chapter figures are "Figure 4.2"; a picture on the intro page would
    otherwise be "Figure 1", the number of one of the paper's own figures.
    """
    changed = []
    for docname in list(env.toc_fignumbers):
        if not env.toc_secnumbers.get(docname) and "figure" in env.toc_fignumbers[docname]:
            env.toc_fignumbers[docname].pop("figure")
            changed.append(docname)
    return changed


def share_html_handlers(app) -> None:
    """Let the one-page builder (``make pdf``) render every node the HTML builder can.

    Sphinx looks node handlers up by builder name first; once any extension
    registers one for "singlehtml", that builder no longer falls back to the
    "html" handlers, and myst-nb's nodes (hidden code cells) have none there.
    """
    handlers = app.registry.translation_handlers
    if app.builder.name in handlers:
        for node, pair in handlers.get("html", {}).items():
            handlers[app.builder.name].setdefault(node, pair)


def setup(app):
    app.connect("doctree-resolved", rewrite_numbers)
    app.connect("builder-inited", share_html_handlers)
    # after Sphinx's toctree collector has numbered the figures (priority 500)
    app.connect("env-get-updated", unnumber_front_matter, priority=900)
    for handler in logging.getLogger("sphinx").handlers:
        if not any(isinstance(f, NoConfigDump) for f in handler.filters):
            handler.addFilter(NoConfigDump())
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
