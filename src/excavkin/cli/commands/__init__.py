"""The general commands of ``excavkin``, one per module, each exposing ``command``."""
