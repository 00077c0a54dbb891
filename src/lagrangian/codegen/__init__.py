"""Code generation: one program form of the equations, printed and loaded by targets."""
