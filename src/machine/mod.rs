//! Five-axis kinematic chains, inverse and direct kinematics (paper 000 eq. 8-10), ISO 230-1
//! location errors and error motions (eq. 11-12, paper 002 eq. 1-2, paper 004 eq. S1-S3).
