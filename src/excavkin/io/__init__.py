"""Reading and writing mechanism files."""

from excavkin.io.toml_model import load_model, loads_model

__all__ = ["load_model", "loads_model"]
