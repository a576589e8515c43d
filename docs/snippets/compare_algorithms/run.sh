mimics battery run compare.toml --out compare --workers 2
mimics battery status compare
