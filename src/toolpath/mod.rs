//! Flank tool path (paper 000 eq. 2), tool envelope and overcut (eq. 3-7), tool profile (paper 001).
