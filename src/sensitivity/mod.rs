//! Machined defect (paper 000 eq. 14), Figure-19 curves, surface-frame coefficients (paper 002).
