"""Stage bodies of the pipeline: read artefacts and configuration, call the physics packages,
write artefacts. ``pipeline.py`` holds the stage graph and the command line."""
