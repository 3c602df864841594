"""The HTML report's page model: blocks, sections and the report, rendered with the jinja2
template ``fogts/report/templates/report.html.j2``.

Rendering autoescapes every string, so file names, column names and comment lines from the
input file - which are untrusted - are shown as text and never interpreted as HTML.  The
document needs nothing from the network: styles are inline, figures are data URIs, it has no
script, and its Content-Security-Policy forbids loading anything else.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["Block", "HtmlReport", "Section"]


@dataclass(frozen=True)
class Block:
    """One piece of a section: ``figure``, ``table``, ``pre``, ``list``, ``heading``,
    ``verdict`` or ``paragraph``.  Every string is plain text (escaped when rendered)."""

    kind: str
    text: str = ""
    caption: str = ""
    # figure
    id: str = ""
    mime: str = ""
    data: str = ""
    alt: str = ""
    width: int = 0
    height: int = 0
    # table
    columns: tuple[str, ...] = ()
    rows: tuple[tuple[str, ...], ...] = ()
    numeric: tuple[bool, ...] = ()
    highlight: tuple[int, ...] = ()
    # list
    items: tuple[str, ...] = ()
    # verdict
    good: bool = True

    def to_dict(self) -> dict[str, Any]:
        """The block's kind and content (a figure's size in bytes instead of its data)."""
        d: dict[str, Any] = {"kind": self.kind}
        if self.kind == "figure":
            d.update(id=self.id, mime=self.mime, bytes=len(self.data) * 3 // 4,
                     caption=self.caption)
        elif self.kind == "table":
            d.update(caption=self.caption, columns=list(self.columns),
                     rows=[list(r) for r in self.rows])
        elif self.kind == "list":
            d.update(caption=self.caption, items=list(self.items))
        else:
            d.update(text=self.text)
        return d


@dataclass(frozen=True)
class Section:
    """A titled part of the report.

    Attributes
    ----------
    id : str
        HTML anchor (built by fogts, never from input strings).
    title : str
    how_to_read : str
        One sentence: what the section shows and how to read it.
    status : str
        ``"ok"`` or ``"error"`` (then ``message`` says why).
    blocks : tuple of Block
    notes : tuple of str
        Warnings raised while computing the section.
    """

    id: str
    title: str
    how_to_read: str
    status: str = "ok"
    message: str = ""
    blocks: tuple[Block, ...] = ()
    notes: tuple[str, ...] = ()

    @property
    def figures(self) -> tuple[Block, ...]:
        """The section's figure blocks."""
        return tuple(b for b in self.blocks if b.kind == "figure")

    def to_dict(self) -> dict[str, Any]:
        """The section as JSON-safe types."""
        return {"id": self.id, "title": self.title, "how_to_read": self.how_to_read,
                "status": self.status, "message": self.message,
                "blocks": [b.to_dict() for b in self.blocks], "notes": list(self.notes)}


@dataclass(frozen=True)
class HtmlReport:
    """A report ready to render.

    Attributes
    ----------
    title, source : str
    generated : str
        UTC time stamp of the build.
    version : str
        fogts version.
    sections : tuple of Section
    omitted : tuple of (str, str)
        Parts left out and why (e.g. no temperature column).
    """

    title: str
    source: str
    generated: str
    version: str
    sections: tuple[Section, ...]
    omitted: tuple[tuple[str, str], ...] = ()

    @property
    def n_figures(self) -> int:
        """Number of figures in all sections."""
        return sum(len(s.figures) for s in self.sections)

    def render(self) -> str:
        """The HTML document (one string, self-contained)."""
        from jinja2 import Environment, PackageLoader, StrictUndefined

        env = Environment(loader=PackageLoader("fogts.report", "templates"), autoescape=True,
                          undefined=StrictUndefined, trim_blocks=False, lstrip_blocks=False,
                          keep_trailing_newline=True)
        template = env.get_template("report.html.j2")
        return template.render(title=self.title, source=self.source,
                               generated=self.generated, version=self.version,
                               sections=self.sections, omitted=self.omitted)

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-safe types (figures by size, not data)."""
        return {"title": self.title, "source": self.source, "generated": self.generated,
                "version": self.version, "sections": [s.to_dict() for s in self.sections],
                "omitted": [{"part": p, "reason": r} for p, r in self.omitted]}

    def to_frame(self) -> Any:
        """One row per section: id, title, status, number of figures, message."""
        import pandas as pd

        return pd.DataFrame([{"id": s.id, "title": s.title, "status": s.status,
                              "figures": len(s.figures), "message": s.message}
                             for s in self.sections])

    def summary(self) -> str:
        """A few lines for the terminal: counts, failed sections, parts not included."""
        bad = [s for s in self.sections if s.status != "ok"]
        lines = [f"report {self.title!r}: {len(self.sections)} section(s), {self.n_figures} "
                 f"figure(s)"]
        lines += [f"  failed: {s.title}: {s.message}" for s in bad]
        lines += [f"  not included: {p} ({r})" for p, r in self.omitted]
        return "\n".join(lines)
