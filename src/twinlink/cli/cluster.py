"""`twinlink cluster up`: a local scale-out cluster for development (twinlink.devcluster)."""

from __future__ import annotations

from pathlib import Path

import click

from twinlink.cli.common import HelpGroup


@click.group(cls=HelpGroup)
def cluster() -> None:
    """A local cluster: PostgreSQL, Kafka, twinlink nodes and haproxy on this machine."""


@cluster.command()
@click.option(
    "--port",
    type=click.IntRange(0, 65535),
    default=8000,
    show_default=True,
    help="The load balancer's port on 127.0.0.1; 0 for any free one (the URL is printed).",
)
@click.option(
    "--mqtt-port",
    type=click.IntRange(0, 65535),
    default=1883,
    show_default=True,
    help="Its MQTT port on 127.0.0.1 (to a ready node); any free one when 0 or taken.",
)
@click.option(
    "--nodes", type=click.IntRange(1, 8), default=2, show_default=True, help="twinlink nodes."
)
@click.option(
    "--data-dir",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path(".twinlink-cluster"),
    show_default=True,
    help="The cluster's folder: data, logs and secrets, kept across starts.",
)
@click.option("--no-demo", is_flag=True, help="Without the example twins and the simulated rig.")
@click.option(
    "--examples",
    type=click.Path(file_okay=False, path_type=Path),
    default=Path("examples"),
    show_default=True,
    help="Folder of the demo's DT documents.",
)
def up(
    port: int, mqtt_port: int, nodes: int, data_dir: Path, no_demo: bool, examples: Path
) -> None:
    """Start PostgreSQL, Kafka, the nodes and haproxy in front of them, with the demo twins;
    Ctrl-C stops them all (twice: kills them). Data and logs stay in --data-dir.

    Needs Debian's postgresql and haproxy, Java 17 and Maven (make cluster installs them)."""
    from twinlink.devcluster.cluster import ClusterError, ClusterOptions, run

    options = ClusterOptions(data_dir, port, mqtt_port, nodes, demo=not no_demo, examples=examples)
    try:
        run(options, lambda line: click.echo(line, err=True))
    except ClusterError as err:
        raise click.ClickException(str(err)) from err
