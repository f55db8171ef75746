//! Least-squares identification of error parameters, identifiability, uncertainty.
