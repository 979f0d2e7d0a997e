"""A self-contained HTML stepper for notebooks: a :class:`~delkit.view.document.Document`'s frames drawn as
SVG (:mod:`delkit.drawing.draw`), precomputed, switched by radio buttons and CSS — no server, no script, so it also
shows in untrusted notebooks. ``planners.view.stepper(task, plan)`` builds one for a plan."""

from __future__ import annotations

import base64
import itertools
from html import escape

from delkit.view.document import Document

__all__ = ["Stepper"]

_IDS = itertools.count()
#: frames' graphs with more worlds than this are summarised, not drawn
MAX_DRAWN = 200


class Stepper:
    """``Stepper(doc)``: ``_repr_html_`` shows one frame at a time with a row of step buttons."""

    def __init__(self, doc: Document) -> None:
        self.doc = doc

    def html(self) -> str:
        from delkit.drawing.draw import picture

        uid = f"dkv{next(_IDS)}"
        n = len(self.doc.frames)
        css = [f"#{uid} .fr{{display:none}}", f"#{uid} input{{display:none}}",
               f"#{uid} label{{border:1px solid #aaa;border-radius:3px;padding:1px 6px;margin:1px;cursor:pointer;"
               f"font:12px sans-serif;display:inline-block}}",
               f"#{uid} .pn{{display:inline-block;vertical-align:top;margin:4px;border:1px solid #ddd}}",
               f"#{uid} h4{{margin:2px 4px;font:bold 12px sans-serif}}"]
        for i in range(n):
            css.append(f"#{uid}-r{i}:checked ~ .fr{i}{{display:block}}")
            css.append(f"#{uid}-r{i}:checked ~ .bar label[for={uid}-r{i}]{{background:#cde}}")
        out = [f'<div id="{uid}" class="delkit-stepper"><style>{"".join(css)}</style>']
        out += [f'<input type="radio" name="{uid}" id="{uid}-r{i}"{" checked" if i == 0 else ""}>' for i in range(n)]
        out.append(f'<div class="bar"><b style="font:13px sans-serif">{escape(self.doc.title)}</b><br>')
        out += [f'<label for="{uid}-r{i}" title="{escape(f.title)}">{escape(f.title.split(":")[0])}</label>'
                for i, f in enumerate(self.doc.frames)]
        out.append("</div>")
        for i, f in enumerate(self.doc.frames):
            out.append(f'<div class="fr fr{i}"><div style="font:bold 13px sans-serif;margin:4px">'
                       f'{escape(f.title)}</div>')
            for p in f.panels:
                size = getattr(p.model, "n_worlds", None) or getattr(p.model, "n_events", 0)
                body = (picture(p.model).svg() if size <= MAX_DRAWN else
                        f"<p>{size} worlds: not drawn (more than {MAX_DRAWN})</p>")
                out.append(f'<div class="pn"><h4>{escape(p.title)}</h4>{body}</div>')
            if f.notes:
                out.append('<ul style="font:12px sans-serif">' + "".join(f"<li>{escape(t)}</li>" for t in f.notes)
                           + "</ul>")
            if f.table:
                out.append('<table style="font:12px sans-serif">' + "".join(
                    "<tr>" + "".join(f"<td>{escape(c)}</td>" for c in row) + "</tr>" for row in f.table) + "</table>")
            if f.image is not None:
                data = base64.b64encode(f.image).decode()
                out.append(f'<img style="max-width:360px" src="data:{f.image_type};base64,{data}">')
            out.append("</div>")
        out.append("</div>")
        return "".join(out)

    def _repr_html_(self) -> str:
        return self.html()
