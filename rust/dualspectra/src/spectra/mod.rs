//! Generalized symmetric eigenproblems $W\phi = \lambda M \phi$ (see `eigensolver`).
