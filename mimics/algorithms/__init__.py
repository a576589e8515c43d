"""Built-in algorithms, one module each; the module name is the algorithm's name."""
