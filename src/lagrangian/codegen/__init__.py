"""Code generation: one program form of the equations and the targets that print it."""
