"""The bottom layer: argument checks, files written atomically, bounded JSON, bundled assets.

Nothing here imports any other part of :mod:`tactile_core`; every other layer may import it.
"""
