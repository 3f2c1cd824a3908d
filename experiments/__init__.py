"""The experiment launcher and its commands (a later issue)."""
