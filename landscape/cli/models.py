"""``landscape models``: the model parameter sets, shipped or in files (what ``--model`` takes)."""

from __future__ import annotations

import click


@click.command("models")
@click.argument("sets", nargs=-1, metavar="[NAME|FILE]...")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON list (as GET /api/model-sets) instead.")
def models(sets, as_json):
    """List model sets: name, version, hash, profile, the elements each switches on and its description.

    Without arguments the sets shipped with the package (the names --model takes); with NAME or FILE (e.g. a
    calibration's best.toml) those, checked as --model checks them.
    """
    from landscape.viz import files
    from sim.model_set import load_model_set, shipped_model_sets

    summaries = [load_model_set(s).summary() for s in (sets or shipped_model_sets())]
    if as_json:
        click.echo(files.json_text(summaries))
        return
    click.echo("| set | version | hash | profile | elements | description |")
    click.echo("|---|---|---|---|---|---|")
    for s in summaries:
        extra = ", ".join(s["elements"]) or "–"
        click.echo(
            f"| {s['name']} | {s['version']} | {s['model_set_hash']} | {s['profile']} | {extra} | "
            f"{s['description']} |"
        )
