/*
 * tir_rules.h - the validation rules of the .tir readers that are data:
 * the MF-Tyre sections and keys grip knows besides its coefficients, and
 * the plausibility range of every coefficient family. ONE table for the C
 * reader (tir_reader.c) and the Python reader
 * (tools/grip_tools/reference/tir.py parses this file), so the two apply
 * the same rules. docs/tools.md ("The .tir reader") explains them.
 *
 * Keep the X(...) lines one per line and their arguments literal: the
 * Python reader reads them with a regular expression.
 */
#ifndef GRIP_TIR_RULES_H
#define GRIP_TIR_RULES_H

/* Bounds of the readers (both): a longer line, a larger file, more keys,
 * table rows or sections is an error naming the bound. */
#define GRIP_TIR_LINE_MAX 4096           /* bytes of one line, without the LF */
#define GRIP_TIR_SIZE_MAX 4194304L       /* bytes of the whole file (4 MiB)   */
#define GRIP_TIR_KEYS_MAX 4096           /* KEY = value lines                 */
#define GRIP_TIR_ROWS_MAX 4096           /* table rows ([SHAPE], ...)         */
#define GRIP_TIR_SECTIONS_MAX 256        /* distinct [SECTION] names          */

/*
 * The sections of MF-Tyre / MF-Swift / Adams PAC2002 / MFeval property
 * files. A section grip's coefficient list (grip_mf_coefs.h) names is
 * known too. Keys in any other section (a vendor's header such as
 * [GOODYEAR]) are not read and not checked, except that a key grip reads
 * found there is reported (a misspelled section would hide it).
 */
#define GRIP_TIR_SECTIONS(X) \
    X(MDI_HEADER) \
    X(UNITS) \
    X(MODEL) \
    X(DIMENSION) \
    X(OPERATING_CONDITIONS) \
    X(INERTIA) \
    X(VERTICAL) \
    X(STRUCTURAL) \
    X(CONTACT_PATCH) \
    X(INFLATION_PRESSURE_RANGE) \
    X(VERTICAL_FORCE_RANGE) \
    X(LONG_SLIP_RANGE) \
    X(SLIP_ANGLE_RANGE) \
    X(INCLINATION_ANGLE_RANGE) \
    X(SCALING_COEFFICIENTS) \
    X(LONGITUDINAL_COEFFICIENTS) \
    X(OVERTURNING_COEFFICIENTS) \
    X(LATERAL_COEFFICIENTS) \
    X(ROLLING_COEFFICIENTS) \
    X(ALIGNING_COEFFICIENTS) \
    X(TURNSLIP_COEFFICIENTS) \
    X(SHAPE) \
    X(DEFLECTION_LOAD_CURVE) \
    X(BOTTOMING_CURVE)

/*
 * Keys the reader itself interprets, with the section it reads them from
 * (besides the coefficients of grip_mf_coefs.h).
 */
#define GRIP_TIR_READ_KEYS(X) \
    X(UNITS, LENGTH) \
    X(UNITS, FORCE) \
    X(UNITS, ANGLE) \
    X(UNITS, MASS) \
    X(UNITS, TIME) \
    X(UNITS, PRESSURE) \
    X(MODEL, FITTYP) \
    X(MODEL, TYRESIDE) \
    X(MODEL, PROPERTY_FILE_FORMAT) \
    X(MODEL, USE_MODE)

/*
 * Keys MF-Tyre, MF-Swift, Adams PAC2002 and MFeval (readTIR) define that
 * grip does not use: accepted in any known section, never read (the
 * turn-slip keys, LMP and [TURNSLIP_COEFFICIENTS], are coefficients of
 * grip_mf_coefs.h). Sources:
 * MFeval's readTIR parameter list, the MF-Tyre 5.2 / PAC2002 property
 * files in tests/data, the MF-Tyre USE_MODE documentation.
 */
#define GRIP_TIR_KNOWN_KEYS(X) \
    X(FILE_TYPE) \
    X(FILE_VERSION) \
    X(FILE_FORMAT) \
    X(ROAD_INCREMENT) \
    X(ROAD_DIRECTION) \
    X(USER_SUB_ID) \
    X(N_TIRE_STATES) \
    X(HMAX_LOCAL) \
    X(TIME_SWITCH_INTEG) \
    X(FUNCTION_NAME) \
    X(SWITCH_INTEG) \
    X(MFSAFE1) \
    X(MFSAFE2) \
    X(MFSAFE3) \
    X(FE_METHOD) \
    X(TYPE) \
    X(RIM_WIDTH) \
    X(MASS) \
    X(IXX) \
    X(IYY) \
    X(BELT_MASS) \
    X(BELT_IXX) \
    X(BELT_IYY) \
    X(GRAVITY) \
    X(VERTICAL_DAMPING) \
    X(MC_CONTOUR_A) \
    X(MC_CONTOUR_B) \
    X(Q_CAM) \
    X(BOTTOM_STIFF) \
    X(YAW_STIFFNESS) \
    X(FREQ_LONG) \
    X(FREQ_LAT) \
    X(FREQ_YAW) \
    X(FREQ_WINDUP) \
    X(DAMP_LONG) \
    X(DAMP_LAT) \
    X(DAMP_YAW) \
    X(DAMP_WINDUP) \
    X(DAMP_RESIDUAL) \
    X(DAMP_VLOW) \
    X(Q_BVX) \
    X(Q_BVT) \
    X(PCMZ1) \
    X(ELLIPS_SHIFT) \
    X(ELLIPS_LENGTH) \
    X(ELLIPS_HEIGHT) \
    X(ELLIPS_ORDER) \
    X(ELLIPS_MAX_STEP) \
    X(ELLIPS_NWIDTH) \
    X(ELLIPS_NLENGTH) \
    X(ENV_C1) \
    X(ENV_C2) \
    X(LGYR) \
    X(QTZ1) \
    X(MBELT)

/*
 * Plausibility ranges, in SI units after the [UNITS] conversion, of every
 * coefficient the file gives (defaults are in range by construction).
 * X(PATTERN, KIND, LO, HI, WHAT): PATTERN is a key, or a prefix ending in
 * '*'; the first matching line applies. KIND:
 *   VAL   LO <= v <= HI
 *   VAL0  v == 0 (not given / not used) or LO <= v <= HI
 *   ABS   LO <= |v| <= HI (sign conventions differ between fitting tools:
 *         the shared G275 files have PDY1 < 0, the MF 6.1 example PKY1 > 0)
 * The limits are MF-Tyre's documented domains and typical values widened
 * to cover every real file in tests/data (chrono-tir, mfeval-tir) and
 * docs/estimator with a margin of 5 to 1000: they catch a unit error (mm
 * in a metre file, kN in a newton file, degrees for radians), a typo
 * (PDY1 = 30000) and a zero that silences a force (PCY1 = 0), not an
 * unusual tyre. GRIP_TIR_NO_RANGE_CHECK / --no-range-check skips them.
 */
#define GRIP_TIR_RANGES(X) \
    X("UNLOADED_RADIUS", VAL, 0.01, 3.0, "unloaded radius [m]") \
    X("WIDTH", VAL0, 0.005, 3.0, "section width [m]") \
    X("ASPECT_RATIO", VAL, 0.05, 2.0, "aspect ratio [-], not percent") \
    X("RIM_RADIUS", VAL0, 0.005, 3.0, "rim radius [m]") \
    X("INFLPRES", VAL0, 5000.0, 5.0e6, "inflation pressure [Pa]") \
    X("NOMPRES", VAL0, 5000.0, 5.0e6, "nominal pressure [Pa]") \
    X("PRESMIN", VAL0, 1000.0, 1.0e7, "pressure range [Pa]") \
    X("PRESMAX", VAL0, 1000.0, 1.0e7, "pressure range [Pa]") \
    X("FNOMIN", VAL, 20.0, 1.0e6, "nominal load [N]") \
    X("FZMIN", VAL, 0.0, 1.0e7, "load range [N]") \
    X("FZMAX", VAL, 0.0, 1.0e7, "load range [N]") \
    X("VERTICAL_STIFFNESS", VAL0, 1000.0, 1.0e9, "vertical stiffness [N/m]") \
    X("LONGITUDINAL_STIFFNESS", VAL0, 1000.0, 1.0e9, "longitudinal stiffness [N/m]") \
    X("LATERAL_STIFFNESS", VAL0, 1000.0, 1.0e9, "lateral stiffness [N/m]") \
    X("LONGVL", VAL, 0.1, 150.0, "reference speed [m/s]") \
    X("VXLOW", VAL, 0.001, 30.0, "low-speed limit [m/s]") \
    X("KPUMIN", VAL, -10.0, 10.0, "slip range [-]") \
    X("KPUMAX", VAL, -10.0, 10.0, "slip range [-]") \
    X("ALPMIN", VAL, -3.2, 3.2, "slip angle range [rad]") \
    X("ALPMAX", VAL, -3.2, 3.2, "slip angle range [rad]") \
    X("CAMMIN", VAL, -3.2, 3.2, "inclination range [rad]") \
    X("CAMMAX", VAL, -3.2, 3.2, "inclination range [rad]") \
    X("Q_RE0", VAL, 0.5, 1.5, "effective radius ratio [-]") \
    X("BREFF", VAL, 0.0, 100.0, "effective radius factor [-]") \
    X("DREFF", VAL, 0.0, 10.0, "effective radius factor [-]") \
    X("BOTTOM_OFFST", VAL, 0.0, 1.0, "bottoming offset [m]") \
    X("Q_FYS*", ABS, 0.0, 1.0e6, "vertical coefficient [-]") \
    X("Q_CAM*", ABS, 0.0, 1.0e4, "vertical camber coefficient [-]") \
    X("L*", VAL, 0.0, 10.0, "scaling factor [-]") \
    X("PCX1", VAL, 0.1, 5.0, "shape factor C, > 0") \
    X("PCY1", VAL, 0.1, 5.0, "shape factor C, > 0") \
    X("QCZ1", VAL, 0.1, 5.0, "shape factor C, > 0") \
    X("RC*", VAL, 0.0, 5.0, "combined-slip shape factor C") \
    X("PDX1", ABS, 0.05, 10.0, "peak friction coefficient") \
    X("PDY1", ABS, 0.05, 10.0, "peak friction coefficient") \
    X("PKX1", ABS, 0.1, 1000.0, "slip stiffness Kx/Fz") \
    X("PKY1", ABS, 0.1, 1000.0, "cornering stiffness Ky/Fz0") \
    X("QBZ1", ABS, 0.1, 1000.0, "trail stiffness factor B") \
    X("PD*", ABS, 0.0, 100.0, "friction coefficient") \
    X("PHYP*", ABS, 0.0, 100.0, "turn-slip shift coefficient [-]") \
    X("PH*", ABS, 0.0, 1.0, "horizontal shift [-]") \
    X("RH*", ABS, 0.0, 1.0, "horizontal shift [-]") \
    X("QH*", ABS, 0.0, 1.0, "horizontal shift [-]") \
    X("PV*", ABS, 0.0, 10.0, "vertical shift [-]") \
    X("PP*", ABS, 0.0, 10.0, "pressure dependency [-]") \
    X("SSZ*", ABS, 0.0, 10.0, "moment arm coefficient [-]") \
    X("PEY3", ABS, 0.0, 1.0e4, "curvature camber coefficient [-]") \
    X("PEY4", ABS, 0.0, 1.0e4, "curvature camber coefficient [-]") \
    X("PEY5", ABS, 0.0, 1.0e4, "curvature camber coefficient [-]") \
    X("RBX3", ABS, 0.0, 1.0e4, "combined-slip camber coefficient [-]") \
    X("RBY4", ABS, 0.0, 1.0e4, "combined-slip camber coefficient [-]") \
    X("RVY3", ABS, 0.0, 1.0e4, "combined-slip shift coefficient [-]") \
    X("RVY6", ABS, 0.0, 1.0e4, "combined-slip shift coefficient [-]") \
    X("P*", ABS, 0.0, 1000.0, "Magic Formula coefficient [-]") \
    X("Q*", ABS, 0.0, 1000.0, "Magic Formula coefficient [-]") \
    X("R*", ABS, 0.0, 1000.0, "Magic Formula coefficient [-]") \
    X("F*", ABS, 0.0, 1000.0, "Magic Formula coefficient [-]")

#endif /* GRIP_TIR_RULES_H */
