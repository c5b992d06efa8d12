"""Planners in any language and any process: the external planner protocol.

srfm sends a planner in another process the episode at its start and an observation at
every step, over a local socket, and gets one command back per step
(docs/planners-any-language.md). The messages are defined once, in ``protocol.toml``
beside this module.

- :func:`define_external` names a planner's command or address; ``external:NAME`` then
  runs it wherever a planner name goes (:func:`srfm.run_episode`, the benchmark,
  ``srfm simulate``, ``srfm benchmark`` with ``--external NAME=COMMAND``);
- :class:`ExternalPlanner` is srfm's end of the connection;
- :func:`serve` (:mod:`srfm.planners.external.client`) makes any Python function a planner at
  the other end.
"""

from srfm.planners.external._planner import (
    ADDRESS_ENV,
    DEFINITIONS_ENV,
    ExternalDefinition,
    ExternalPlanner,
    define_external,
    external_definition,
    is_external,
)
from srfm.planners.external._schema import PROTOCOL_VERSION, SCHEMA_FILE, field_table
from srfm.planners.external.client import Episode, Step, serve

__all__ = [
    "ADDRESS_ENV",
    "DEFINITIONS_ENV",
    "PROTOCOL_VERSION",
    "SCHEMA_FILE",
    "Episode",
    "ExternalDefinition",
    "ExternalPlanner",
    "Step",
    "define_external",
    "external_definition",
    "field_table",
    "is_external",
    "serve",
]
