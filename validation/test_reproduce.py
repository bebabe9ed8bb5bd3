"""CI runs the quick tier of ``validation/reproduce.py``: every claim agrees with RESULTS.md."""

import io
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import reproduce  # noqa: E402


def test_quick_tier_agrees_with_results_md():
    table = io.StringIO()
    rows = reproduce.run("quick", out=table)
    assert len(rows) == sum(c.tier == "quick" for c in reproduce.CLAIMS)
    bad = [f"{c.claim}: {shown}" for c, shown, ok, _ in rows if not ok]
    assert not bad, table.getvalue()
    results = (Path(reproduce.__file__).parent / "RESULTS.md").read_text()
    assert "python validation/reproduce.py" in results   # the table's command is documented
