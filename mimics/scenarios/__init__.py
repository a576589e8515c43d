"""Built-in scenarios, one module each with ``scenario(**params) -> Scenario``."""
