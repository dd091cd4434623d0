/*
 * grip_mf_coefs.h - the Magic Formula coefficients grip reads from a .tir
 * file: ONE list, used by the C parameter struct (grip_mf.h), the host .tir
 * reader (port/linux) and the Python tools (tools/grip_tools/reference/tir.py reads this
 * file), so the three can never disagree.
 *
 * X(field, KEY, SECTION, FORMAT, DEFAULT, REQUIRED)
 *   field     struct member (the .tir key in lower case)
 *   KEY       .tir key; SECTION its [SECTION]
 *   FORMAT    QS or QL fixed-point format (grip_types.h); values in SI units
 *   DEFAULT   value when the key is absent: MFeval's readTIR default
 *             (the values of Pacejka's book tyre) for every coefficient of
 *             the force and moment equations (scaling factors 1, LMUV 0 as
 *             in MF-Tyre, PKY2 1 and PKY4 2, RBX1 20, RCX1 1, PKY6 -1, ...):
 *             0 where MFeval has another value is a silently wrong tyre
 *             (PKY2 = 0 divides Fz by zero inside the atan and takes the
 *             cornering stiffness to 0; RBX1 = 0 removes the combined-slip
 *             weighting). The keys of the extended outputs
 *             (grip_mf_eval_ext, from ASPECT_RATIO on) take MFeval's
 *             defaults too, except RIM_RADIUS (0: no bottoming check,
 *             docs/magic-formula.md); WIDTH, the three STIFFNESS keys, the
 *             *_RANGE limits and the pressures keep 0 = not given (a book
 *             tyre's size or limits would be wrong for any other tyre).
 *             The turn-slip keys (LMP and [TURNSLIP_COEFFICIENTS], used
 *             only with GRIP_MF_USE_TURN_SLIP) default to 0 = not given
 *             (LMP to 1): a set without PHYP1 > 0 and 0 < QDRP1 < 2 cannot
 *             evaluate turn slip. All of them are dimensionless (they
 *             multiply R0 phi), so [UNITS] never scales them
 *   REQUIRED  1: a file without this key is rejected
 */
#ifndef GRIP_MF_COEFS_H
#define GRIP_MF_COEFS_H

#define GRIP_MF_COEFFICIENTS(X) /* grip-deviation: MISRA-20.7 X-macro: X is a macro name */ \
    X(longvl, LONGVL, MODEL, QS, 16.7, 0) \
    X(vxlow, VXLOW, MODEL, QS, 1, 0) \
    X(unloaded_radius, UNLOADED_RADIUS, DIMENSION, QS, 0, 1) \
    X(width, WIDTH, DIMENSION, QS, 0, 0) \
    X(inflpres, INFLPRES, OPERATING_CONDITIONS, QL, 0, 0) \
    X(nompres, NOMPRES, OPERATING_CONDITIONS, QL, 0, 0) \
    X(fnomin, FNOMIN, VERTICAL, QL, 0, 1) \
    X(vertical_stiffness, VERTICAL_STIFFNESS, VERTICAL, QL, 0, 0) \
    X(longitudinal_stiffness, LONGITUDINAL_STIFFNESS, STRUCTURAL, QL, 0, 0) \
    X(lateral_stiffness, LATERAL_STIFFNESS, STRUCTURAL, QL, 0, 0) \
    X(pcfx1, PCFX1, STRUCTURAL, QS, 0, 0) \
    X(pcfx2, PCFX2, STRUCTURAL, QS, 0, 0) \
    X(pcfx3, PCFX3, STRUCTURAL, QS, 0, 0) \
    X(pcfy1, PCFY1, STRUCTURAL, QS, 0, 0) \
    X(pcfy2, PCFY2, STRUCTURAL, QS, 0, 0) \
    X(pcfy3, PCFY3, STRUCTURAL, QS, 0, 0) \
    X(presmin, PRESMIN, INFLATION_PRESSURE_RANGE, QL, 0, 0) \
    X(presmax, PRESMAX, INFLATION_PRESSURE_RANGE, QL, 0, 0) \
    X(fzmin, FZMIN, VERTICAL_FORCE_RANGE, QL, 0, 0) \
    X(fzmax, FZMAX, VERTICAL_FORCE_RANGE, QL, 0, 0) \
    X(kpumin, KPUMIN, LONG_SLIP_RANGE, QS, -1.5, 0) \
    X(kpumax, KPUMAX, LONG_SLIP_RANGE, QS, 1.5, 0) \
    X(alpmin, ALPMIN, SLIP_ANGLE_RANGE, QS, -1.5708, 0) \
    X(alpmax, ALPMAX, SLIP_ANGLE_RANGE, QS, 1.5708, 0) \
    X(cammin, CAMMIN, INCLINATION_ANGLE_RANGE, QS, -0.5236, 0) \
    X(cammax, CAMMAX, INCLINATION_ANGLE_RANGE, QS, 0.5236, 0) \
    X(lfzo, LFZO, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lcx, LCX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lmux, LMUX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lex, LEX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lkx, LKX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lhx, LHX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lvx, LVX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lcy, LCY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lmuy, LMUY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(ley, LEY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lky, LKY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lkyc, LKYC, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lkzc, LKZC, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lhy, LHY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lvy, LVY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lgax, LGAX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lgay, LGAY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lgaz, LGAZ, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(ltr, LTR, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lres, LRES, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lxal, LXAL, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lyka, LYKA, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lvyka, LVYKA, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(ls, LS, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lmuv, LMUV, SCALING_COEFFICIENTS, QS, 0, 0) \
    X(pcx1, PCX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 1) \
    X(pdx1, PDX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 1) \
    X(pdx2, PDX2, LONGITUDINAL_COEFFICIENTS, QS, -0.15, 0) \
    X(pdx3, PDX3, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pex1, PEX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pex2, PEX2, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pex3, PEX3, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pex4, PEX4, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pkx1, PKX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 1) \
    X(pkx2, PKX2, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pkx3, PKX3, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(phx1, PHX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(phx2, PHX2, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pvx1, PVX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pvx2, PVX2, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(ppx1, PPX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(ppx2, PPX2, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(ppx3, PPX3, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(ppx4, PPX4, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(rbx1, RBX1, LONGITUDINAL_COEFFICIENTS, QS, 20, 0) \
    X(rbx2, RBX2, LONGITUDINAL_COEFFICIENTS, QS, 15, 0) \
    X(rbx3, RBX3, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(rcx1, RCX1, LONGITUDINAL_COEFFICIENTS, QS, 1, 0) \
    X(rex1, REX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(rex2, REX2, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(rhx1, RHX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(ptx1, PTX1, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(ptx2, PTX2, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(ptx3, PTX3, LONGITUDINAL_COEFFICIENTS, QS, 0, 0) \
    X(pcy1, PCY1, LATERAL_COEFFICIENTS, QS, 0, 1) \
    X(pdy1, PDY1, LATERAL_COEFFICIENTS, QS, 0, 1) \
    X(pdy2, PDY2, LATERAL_COEFFICIENTS, QS, -0.15, 0) \
    X(pdy3, PDY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pey1, PEY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pey2, PEY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pey3, PEY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pey4, PEY4, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pey5, PEY5, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pky1, PKY1, LATERAL_COEFFICIENTS, QS, 0, 1) \
    X(pky2, PKY2, LATERAL_COEFFICIENTS, QS, 1, 0) \
    X(pky3, PKY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pky4, PKY4, LATERAL_COEFFICIENTS, QS, 2, 0) \
    X(pky5, PKY5, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pky6, PKY6, LATERAL_COEFFICIENTS, QS, -1, 0) \
    X(pky7, PKY7, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(phy1, PHY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(phy2, PHY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(phy3, PHY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pvy1, PVY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pvy2, PVY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pvy3, PVY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pvy4, PVY4, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(ppy1, PPY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(ppy2, PPY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(ppy3, PPY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(ppy4, PPY4, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(ppy5, PPY5, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rby1, RBY1, LATERAL_COEFFICIENTS, QS, 10, 0) \
    X(rby2, RBY2, LATERAL_COEFFICIENTS, QS, 10, 0) \
    X(rby3, RBY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rby4, RBY4, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rcy1, RCY1, LATERAL_COEFFICIENTS, QS, 1, 0) \
    X(rey1, REY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rey2, REY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rhy1, RHY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rhy2, RHY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rvy1, RVY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rvy2, RVY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rvy3, RVY3, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(rvy4, RVY4, LATERAL_COEFFICIENTS, QS, 20, 0) \
    X(rvy5, RVY5, LATERAL_COEFFICIENTS, QS, 2, 0) \
    X(rvy6, RVY6, LATERAL_COEFFICIENTS, QS, 10, 0) \
    X(pty1, PTY1, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(pty2, PTY2, LATERAL_COEFFICIENTS, QS, 0, 0) \
    X(qbz1, QBZ1, ALIGNING_COEFFICIENTS, QS, 0, 1) \
    X(qbz2, QBZ2, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qbz3, QBZ3, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qbz4, QBZ4, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qbz5, QBZ5, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qbz6, QBZ6, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qbz9, QBZ9, ALIGNING_COEFFICIENTS, QS, 10, 0) \
    X(qbz10, QBZ10, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qcz1, QCZ1, ALIGNING_COEFFICIENTS, QS, 0, 1) \
    X(qdz1, QDZ1, ALIGNING_COEFFICIENTS, QS, 0, 1) \
    X(qdz2, QDZ2, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qdz3, QDZ3, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qdz4, QDZ4, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qdz6, QDZ6, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qdz7, QDZ7, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qdz8, QDZ8, ALIGNING_COEFFICIENTS, QS, -0.05, 0) \
    X(qdz9, QDZ9, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qdz10, QDZ10, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qdz11, QDZ11, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qez1, QEZ1, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qez2, QEZ2, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qez3, QEZ3, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qez4, QEZ4, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qez5, QEZ5, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qhz1, QHZ1, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qhz2, QHZ2, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qhz3, QHZ3, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(qhz4, QHZ4, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(ppz1, PPZ1, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(ppz2, PPZ2, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(ssz1, SSZ1, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(ssz2, SSZ2, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(ssz3, SSZ3, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(ssz4, SSZ4, ALIGNING_COEFFICIENTS, QS, 0, 0) \
    X(aspect_ratio, ASPECT_RATIO, DIMENSION, QS, 0.6, 0) \
    X(rim_radius, RIM_RADIUS, DIMENSION, QS, 0, 0) \
    X(q_re0, Q_RE0, VERTICAL, QS, 1, 0) \
    X(q_v1, Q_V1, VERTICAL, QS, 0, 0) \
    X(q_v2, Q_V2, VERTICAL, QS, 0, 0) \
    X(q_fz2, Q_FZ2, VERTICAL, QS, 1.0e-4, 0) \
    X(q_fcx, Q_FCX, VERTICAL, QS, 0, 0) \
    X(q_fcy, Q_FCY, VERTICAL, QS, 0, 0) \
    X(q_fcy2, Q_FCY2, VERTICAL, QS, 0, 0) \
    X(q_cam1, Q_CAM1, VERTICAL, QS, 0, 0) \
    X(q_cam2, Q_CAM2, VERTICAL, QS, 0, 0) \
    X(q_cam3, Q_CAM3, VERTICAL, QS, 0, 0) \
    X(q_fys1, Q_FYS1, VERTICAL, QL, 0, 0) \
    X(q_fys2, Q_FYS2, VERTICAL, QL, 0, 0) \
    X(q_fys3, Q_FYS3, VERTICAL, QL, 0, 0) \
    X(pfz1, PFZ1, VERTICAL, QS, 0, 0) \
    X(breff, BREFF, VERTICAL, QS, 8.4, 0) \
    X(dreff, DREFF, VERTICAL, QS, 0.27, 0) \
    X(freff, FREFF, VERTICAL, QS, 0.07, 0) \
    X(bottom_offst, BOTTOM_OFFST, VERTICAL, QS, 0.01, 0) \
    X(q_a1, Q_A1, VERTICAL, QS, 0, 0) \
    X(q_a2, Q_A2, VERTICAL, QS, 0, 0) \
    X(q_ra1, Q_RA1, CONTACT_PATCH, QS, 0.5, 0) \
    X(q_ra2, Q_RA2, CONTACT_PATCH, QS, 1, 0) \
    X(q_rb1, Q_RB1, CONTACT_PATCH, QS, 1, 0) \
    X(q_rb2, Q_RB2, CONTACT_PATCH, QS, -1, 0) \
    X(lsgkp, LSGKP, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lsgal, LSGAL, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lmx, LMX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lvmx, LVMX, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(lmy, LMY, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(qsx1, QSX1, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx2, QSX2, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx3, QSX3, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx4, QSX4, OVERTURNING_COEFFICIENTS, QS, 5, 0) \
    X(qsx5, QSX5, OVERTURNING_COEFFICIENTS, QS, 1, 0) \
    X(qsx6, QSX6, OVERTURNING_COEFFICIENTS, QS, 10, 0) \
    X(qsx7, QSX7, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx8, QSX8, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx9, QSX9, OVERTURNING_COEFFICIENTS, QS, 0.4, 0) \
    X(qsx10, QSX10, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx11, QSX11, OVERTURNING_COEFFICIENTS, QS, 5, 0) \
    X(qsx12, QSX12, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx13, QSX13, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsx14, QSX14, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(ppmx1, PPMX1, OVERTURNING_COEFFICIENTS, QS, 0, 0) \
    X(qsy1, QSY1, ROLLING_COEFFICIENTS, QS, 0.01, 0) \
    X(qsy2, QSY2, ROLLING_COEFFICIENTS, QS, 0, 0) \
    X(qsy3, QSY3, ROLLING_COEFFICIENTS, QS, 4.0e-4, 0) \
    X(qsy4, QSY4, ROLLING_COEFFICIENTS, QS, 4.0e-5, 0) \
    X(qsy5, QSY5, ROLLING_COEFFICIENTS, QS, 0, 0) \
    X(qsy6, QSY6, ROLLING_COEFFICIENTS, QS, 0, 0) \
    X(qsy7, QSY7, ROLLING_COEFFICIENTS, QS, 0.85, 0) \
    X(qsy8, QSY8, ROLLING_COEFFICIENTS, QS, -0.4, 0) \
    X(lmp, LMP, SCALING_COEFFICIENTS, QS, 1, 0) \
    X(pdxp1, PDXP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pdxp2, PDXP2, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pdxp3, PDXP3, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pkyp1, PKYP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pdyp1, PDYP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pdyp2, PDYP2, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pdyp3, PDYP3, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pdyp4, PDYP4, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(phyp1, PHYP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(phyp2, PHYP2, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(phyp3, PHYP3, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(phyp4, PHYP4, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pecp1, PECP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(pecp2, PECP2, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(qdtp1, QDTP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(qcrp1, QCRP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(qcrp2, QCRP2, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(qbrp1, QBRP1, TURNSLIP_COEFFICIENTS, QS, 0, 0) \
    X(qdrp1, QDRP1, TURNSLIP_COEFFICIENTS, QS, 0, 0)

#endif /* GRIP_MF_COEFS_H */
