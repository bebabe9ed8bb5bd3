"""validation/errata.md states, equation by equation, what errata_check.py found.

The per-equation verdicts of the audited tables (Charan SM Eqs. 9-35 and
45-61; Ishima Eqs. 36-37, D8-D23, F1-F36) are typed in the page beside their
reasons; the recorded run of the claim ``kernels.errata`` holds the verdict
the script computed for each.  Every audited equation the page lists must
carry the recorded verdict (bold and "(sign)" are emphasis, not verdicts).
"""

import json
import re
from pathlib import Path

HERE = Path(__file__).resolve().parent
AUDITED = {"Charan": ("### SM Eqs. 9-35", "### Unnumbered statements"),
           "Ishima": ("### Eqs. 36-37", "## Summary")}


def _labels(cell):
    """'17, 18' -> ['17', '18']; '53-55' -> ['53', '54', '55']; 'F19-F22' likewise."""
    out = []
    for part in re.split(r",\s*", cell.strip("* ")):
        m = re.fullmatch(r"([A-Z]?)(\d+)(?:\s*-\s*([A-Z]?)(\d+))?", part.strip())
        if m:
            first, last = int(m.group(2)), int(m.group(4) or m.group(2))
            out += [f"{m.group(1)}{n}" for n in range(first, last + 1)]
    return out


def _verdict(cell):
    text = cell.replace("*", "").strip()
    return text.replace(" (sign)", "")


def _page_verdicts(paper):
    page = (HERE / "errata.md").read_text()
    start, end = AUDITED[paper]
    part = page[page.index(start):page.index(end, page.index(start))]
    out = {}
    for row in re.findall(r"^\|([^|\n]+)\|[^|\n]*\|([^|\n]+)\|", part, re.M):
        for label in _labels(row[0]):
            out[label] = _verdict(row[1])
    return out


def test_every_audited_verdict_is_the_recorded_one():
    rec = json.loads((HERE / "records" / "kernels.errata.json").read_text())
    checked = 0
    for paper in AUDITED:
        recorded = rec["values"]["equations"][paper]
        for label, verdict in _page_verdicts(paper).items():
            if label not in recorded:
                continue
            assert verdict == recorded[label], (paper, label, verdict, recorded[label])
            checked += 1
    counts = rec["values"]["counts"]
    assert checked == counts["Charan"]["checked"] + counts["Ishima"]["checked"]
