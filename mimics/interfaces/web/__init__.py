"""The workbench: `mimics ui`, a local web application on the lower layers (see app.py)."""
