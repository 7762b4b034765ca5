"""Reading `voussoir run --json` results, for the scripts that compare two builds over the seed
domain (seed_check.sh, dae_check.sh): a result file, its collapsing limit point and its hinges at
collapse. Standard library only."""
import json


def load(path):
    """The JSON object in path, or None when it is missing or unreadable (a run that failed)."""
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def collapse_lp(d):
    """The collapsing limit point (mm): the last limit point of kind "collapse", where the arch
    left its last stable equilibrium; None when the run did not collapse."""
    lps = [lp for lp in (d or {}).get("limit_points") or [] if lp.get("kind") == "collapse"]
    return lps[-1]["delta_mm"] if lps else None


def hinges(d):
    """The hinges at collapse as text, by first joint: "A:3-i B:9-e ..." (label:joints-side)."""
    col = (d or {}).get("collapse") or {}
    hs = sorted(col.get("hinges") or [], key=lambda h: h["joints"][0])
    return " ".join(f"{h['label']}:{'-'.join(map(str, h['joints']))}-{h['side']}" for h in hs)
