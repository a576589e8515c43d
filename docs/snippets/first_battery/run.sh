mimics battery run battery.toml --out night --workers 2
