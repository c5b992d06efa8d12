"""Dataset adapters (JRDB, ETH/UCY, NavWareSet) to canonical trajectories and MCAP.

Every adapter turns its raw layout (documented in the repository's top-level
``datasets/`` folder) into a list of :class:`Trajectories`, one per scene; scenes are
written to and read from MCAP files with :func:`write_mcap` and :func:`read_mcap`::

    from srfm.datasets import eth_ucy, read_mcap, write_mcap

    scenes = eth_ucy.read_eth_ucy("data/eth_ucy", dt_overrides={"biwi_eth.txt": 0.6667})
    write_mcap("eth_ucy.mcap", scenes, dataset="eth-ucy")
    data = read_mcap("eth_ucy.mcap")
"""

from srfm.datasets import eth_ucy, jrdb, navwareset
from srfm.datasets._mcap import (
    FRAME_SCHEMA,
    SCHEMA_NAME,
    SCHEMA_VERSION,
    DatasetFile,
    read_mcap,
    write_mcap,
)
from srfm.datasets._trajectories import (
    AGENT_KINDS,
    PEDESTRIAN,
    ROBOT,
    DatasetWarning,
    Trajectories,
)
from srfm.datasets.eth_ucy import read_eth_ucy
from srfm.datasets.jrdb import read_jrdb
from srfm.datasets.navwareset import read_navwareset

__all__ = [
    "AGENT_KINDS",
    "FRAME_SCHEMA",
    "PEDESTRIAN",
    "ROBOT",
    "SCHEMA_NAME",
    "SCHEMA_VERSION",
    "DatasetFile",
    "DatasetWarning",
    "Trajectories",
    "eth_ucy",
    "jrdb",
    "navwareset",
    "read_eth_ucy",
    "read_jrdb",
    "read_mcap",
    "read_navwareset",
    "write_mcap",
]
