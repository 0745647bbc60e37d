"""The command modules of ``pipeline.py`` that are more than a few lines: each adds its arguments
(``add_args(parser)``) and runs (``command(args)`` -> exit status).

* ``geometry`` — ``pipeline.py geometry``: the wheel/rail contact of the study's operating point;
* ``stability`` — ``pipeline.py stability``: the linear stability screen of a configuration;
* ``maps`` — ``pipeline.py map``: squeal maps and their time-domain confirmations.

``pipeline.py`` parses the command line and maps errors to exit statuses; the stage bodies live in
``stages/``, the exports in ``exports/`` and the stand-alone contact command in ``contact/cli.py``.
Nothing below ``cli`` imports it.
"""
