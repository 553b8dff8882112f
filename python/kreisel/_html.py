"""Rich HTML views of tops for notebooks (``_repr_html_``)."""

from __future__ import annotations

import html


def table(title: str, call: str, rows, notes=()) -> str:
    """An HTML card: the title, the call that makes the object, a table of
    ``(name, value, units, meaning)`` rows and notes (derived quantities)."""
    body = "".join(
        f"<tr><td><code>{html.escape(name)}</code></td><td>{html.escape(_fmt(value))}</td>"
        f"<td>{html.escape(units)}</td><td>{html.escape(meaning)}</td></tr>"
        for name, value, units, meaning in rows
    )
    extra = "".join(f"<br><small>{html.escape(n)}</small>" for n in notes)
    return (
        f"<div><b>{html.escape(title)}</b><br><small><code>{html.escape(call)}</code></small>"
        f"<table><thead><tr><th>parameter</th><th>value</th><th>units</th><th>meaning</th>"
        f"</tr></thead><tbody>{body}</tbody></table>{extra}</div>"
    )


def _fmt(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)
