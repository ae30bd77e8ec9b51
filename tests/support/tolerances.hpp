#pragma once
// the named tolerances of the tests (camopt::test::tol), each with the reason for its size;
// the checks that use them are in support/compare.hpp

namespace camopt::test {

// named tolerances, each with the reason for its size
namespace tol {
// the kinematics engine against closed forms, each relative to the peak magnitude of the same
// quantity over the sweep (docs/kinematics.md#accuracy): position solves to ~1e-12, the
// derivatives come from implicit differentiation of the same solve
inline constexpr double kDisplacementRel = 1e-9;
inline constexpr double kVelocityRel = 1e-7;
inline constexpr double kAccelerationRel = 1e-7;
inline constexpr double kJerkRel = 1e-5;
inline constexpr double kOrderRel[4] = {kDisplacementRel, kVelocityRel, kAccelerationRel, kJerkRel};

// round-off
inline constexpr double kUlpRel = 1e-15;           // one closed form evaluated along two paths: a few ulps
inline constexpr double kUlpAbs = 1e-15;           // the same, for a quantity of size ~1 that may be 0
inline constexpr double kOctantTrigAbs = 2.3e-16;    // sin/cos from the first octant: libm's error there, below an ulp of 1
inline constexpr double kReorderedSumRel = 1e-14;  // the same sum accumulated in another order

// finite differences (tests/oracles/finite_difference.hpp): truncation + round-off at the step used
inline constexpr double kCentral8Step1e3Rel = 1e-11;  // 8th order at h = 1e-3: truncation ~1e-24 f^(9), round-off ~1e-13
inline constexpr double kCentral2Step1e5Rel = 1e-8;   // 2-point at h = 1e-5: truncation h^2 f'''/6 ~1e-10, round-off ~1e-11

// jets and splines (core)
inline constexpr double kJetRecurrenceRel = 1e-13;     // Taylor recurrences against a symbolic closed form
inline constexpr double kJetRecurrenceAbs = 1e-14;     // the same, for references that are ~0
inline constexpr double kJetTwoFormsRel = 1e-12;       // two jet formulations of one function (atan2 vs atan(y/x), compose vs direct)
inline constexpr double kSplineJetRel = 1e-14;         // a spline's jet overload against its scalar derivatives
inline constexpr double kSplineNodeAbs = 1e-12;        // interpolation at the data sites, |f| ~ 1: solve round-off
inline constexpr double kSplineContinuityRel = 1e-9;   // left/right limits at a knot, of max |f^(k)| (f'''' amplifies round-off)
inline constexpr double kSplineWrapRel = 1e-12;        // f^(k)(x + 3 period) vs f^(k)(x): x + 3 period rounds by ~1e-15 rad
inline constexpr double kSplineSolverRel = 1e-12;      // two solvers of one spline system (sparse LU, banded), of the peak
inline constexpr double kCyclicFilterRel = 4e-15;      // residual of the recursive cyclic filter, of the right-hand side
inline constexpr double kSplineIntegralRel = 1e-12;    // exact piecewise integral against Gauss-Legendre
inline constexpr double kSplinePolyAbs = 1e-10;        // reproduction of a quadratic (f'' amplifies round-off by 1/h^2)
inline constexpr double kNaturalEndThirdAbs = 1e-9;    // f''' = 0 at a natural end: solve round-off / h^3
inline constexpr double kNaturalEndFourthAbs = 1e-8;   // f'''' = 0 at a natural end: solve round-off / h^4
inline constexpr double kSplineExtrapolationAbs = 1e-14;  // linear extrapolation a + a' d against the same line, |f| ~ 1
inline constexpr double kSplineExtremeAbs = 1e-6;      // a spline's extreme against the function's: interpolation error at 40 knots

// kinematics: contact outputs and derivatives (tests/kinematics)
inline constexpr double kContactPointRel = kDisplacementRel;  // contact point and normal, of the mechanism size
inline constexpr double kPressureAngleAbs = 1e-9;   // [rad] a position-level angle against its closed form
inline constexpr double kContactRateRel = kVelocityRel;  // roller speed, sliding, entrainment (per rad of cam), of the peak
inline constexpr double kCurvatureRel = 1e-9;       // a position-level output (curvature) against its closed form
inline constexpr double kKernelFdRel = 1e-7;        // solved jets against 6th/8th-order central differences at 1e-3 rad, of the peak
inline constexpr double kNewtonCentringAbs = 1e-6;  // [deg of u] four Newton steps centring a sample in its table piece
inline constexpr double kGapAbs = 1e-12;            // [mm] a contact's clearance against its closed form: solve round-off
inline constexpr double kLiftLossAbs = 1e-12;       // [mm] a summary's peak lift against its closed form
inline constexpr double kPeakAngleAbs = 1e-6;       // [deg] the refined angle of a symmetric peak
inline constexpr double kSweepCountAbs = 2.0;       // points of a span counted on the sweep grid: one at each end
inline constexpr double kPoseAbs = 1e-9;            // [mm] a point that the constraints hold in place
inline constexpr double kSolverPathAbs = 1e-9;      // [mm or rad] two solve paths, each to 1e-13 x size, through the chain's conditioning
inline constexpr double kPrescribedAbs = 1e-11;     // [mm] a prescribed solve against the whole solve, one point
inline constexpr double kOutputLiftRel = 1e-12;     // output lift against raw - rest: one subtraction, of max(1, |raw|)
inline constexpr double kGridPeakAbs = 1e-12;       // [mm] the refined peak never below the grid's (one rounding)
inline constexpr double kEccentricSolveAbs = 1e-11; // [mm] solved eccentric flat-follower lift (Newton to 1e-13 x size)
inline constexpr double kEccentricRateAbs = 1e-9;   // [mm/rad^k] its derivatives by implicit differentiation
inline constexpr double kBruteForceLiftAbs = 1e-8;  // [mm] kernel lift against a brute-force touching height (resolves ~1e-11 mm)
inline constexpr double kChordSpline24Abs = 2e-6;   // [mm] lift from a 24-point chord-length cubic spline contour; O(h^4) below (measured 1.4e-6)
inline constexpr double kTransmissionSineAbs = 1e-4;  // a transmission sine against its value printed to 4 digits
inline constexpr double kPrintedLiftAbs = 0.01;     // [mm] a design's max lift against its documented 3-digit value
inline constexpr double kPrintedLimitAbs = 0.01;    // [deg] a reported limit against its 2-decimal value
inline constexpr double kPrintedRadiusAbs = 1e-3;   // [mm] a profile radius against its documented value
inline constexpr double kPrintedMaxRadiusAbs = 2e-3;  // [mm] the same for the max radius read off a measured table
inline constexpr double kPrintedValveLiftAbs = 5e-4;  // [mm] a valve lift against its value printed to 3 decimals
inline constexpr double kTaylorShiftAbs = 8 * 2.220446049250313e-16 * 10.0;  // a degree-4 Taylor shift: 8 roundings of terms up to ~10
inline constexpr double kPointSeriesAbs = 4 * 2.220446049250313e-16;  // profile point series vs the jet evaluation, of their size (same operations)
inline constexpr double kPointSeriesShiftAbs = 16 * 2.220446049250313e-16;  // a shifted memo entry vs a fresh evaluation, of their size
inline constexpr double kPointCoordAbs = 4 * 2.220446049250313e-16 * 30.0;  // [mm] point and slope, |x| <= 30: 4 roundings
inline constexpr double kPointCurvAbs = 4 * 2.220446049250313e-16 * 300.0;  // second derivative, |x''| <= 300: 4 roundings
inline constexpr double kRotatedSinCosAbs = 2 * 2.220446049250313e-16;      // sin, cos rotated by a small angle: two ulps of 1
inline constexpr double kVariableGearAbs[4] = {1e-13, 1e-12, 1e-11, 1e-10};  // a variable gear's jet: Newton to 1e-13, each order one more 1/h
inline constexpr double kGearInverseAbs[3] = {1e-12, 1e-12, 1e-11};          // its inverse, the same
inline constexpr double kFastGeneralRel[4] = {1e-10, 1e-9, 1e-8, 1e-7};  // two contact formulations, each solved to 1e-13: round-off ~1e-11 of each order's peak
inline constexpr double kFastGeneralContactRel = 1e-8;  // their contact quantities and condition numbers, of the peak
inline constexpr double kPrescribedRel[4] = {1e-12, 1e-11, 1e-10, 1e-9};  // a prescribed pose vs the whole solve from the same bits: round-off, of each order's peak
inline constexpr double kRefinedPeakRel = 0.01;    // the refined peak above the peak of a 2-deg grid: the lift's curvature over a step
inline constexpr double kRefinedPeakAbs = 1e-9;     // [mm] the same, for a peak of ~0

// stress (tests/stress)
inline constexpr double kConditionRel = 1e-6;        // a link's condition number against its closed form, near toggle
inline constexpr double kSummaryOfSameRel = 1e-12;   // a summary's extreme against the extreme of the same per-point values
inline constexpr double kRefinedExtremeRel = 1e-6;   // a refined extreme against the largest of a 0.5-deg grid's closed forms
inline constexpr double kQuasiStaticForceRel = 1e-2; // compliant contact forces against rigid ones at <= 10 rpm: the deflection's share of the peak

// contact extremes refined between grid points (tests/kinematics/contact_extremes_test.cpp)
inline constexpr double kRefinedContactRel = 1e-11;    // a refined pressure angle, roller speed or radius against its closed form: a solve's round-off
inline constexpr double kRefinedLocationDeg = 1e-9;    // [deg] where it lies: Brent's method alone gives ~3e-6 deg (sqrt(2 eps / |f''|)), the newton polish ~1e-10
inline constexpr double kCircleRadiusRel = 1e-12;      // a disc's radius from the refined curvature of its surface: round-off of 1 / (1 / R)
inline constexpr double kFineGridStepDeg = 0.01;       // [deg] a refined extreme's location against the best point of a 0.01 deg grid: one step
inline constexpr double kPrintedFootRadiusAbs = 0.05;  // [mm] the CVVL swing cam's concave foot against the -14.7 mm quoted in the docs

// oracles, synthesis and optimisation
// the closed-form oracles against themselves (tests/oracles)
inline constexpr double kOracleFdRel = 1e-7;           // a closed form's derivatives against 8th-order central differences of its own displacement, of the peak
inline constexpr double kExactStencilRel = 1e-8;       // a stencil exact for the polynomial it differences: round-off eps f / h^3 only
inline constexpr double kOracleRoundOffAbs = 1e-14;    // [mm] a closed form against the same closed form written out, |x| ~ 4 mm
inline constexpr double kClosureAbs = 1e-11;           // [mm] loop closure of a closed-form position, links ~50 mm
inline constexpr double kOracleTwoFormsRel = 1e-12;    // one mechanism by two closed forms (a roller as a slider-crank, a disc as a polar cam), of max(1, |x|)
inline constexpr double kOraclePressureAngleAbs = 1e-12;  // [rad] a pressure angle against the angle of the contact normal
inline constexpr double kCouplerDirectionAbs = 1e-13;  // [rad] the coupler's direction from its end points against its solved angle
inline constexpr double kFourBarInverseAbs = 1e-12;    // [rad] the crank angle back through the inverted four-bar
inline constexpr double kInverseRateRel[4] = {0.0, 1e-10, 1e-10, 1e-9};  // an inverse's derivatives (x' = 1/y', ...) with |y'| > 0.05, of max(1, |x^(k)|)
inline constexpr double kSliderCrankInverseAbs = 1e-11;  // [rad] crank and rod angles back from the slider position
inline constexpr double kSupportPointRel = 1e-14;      // the contact point's height against the support function: a few roundings
inline constexpr double kSupportContactAbs = 1e-12;    // [mm] the contact point along the face, and the slack of "farthest along the normal"
inline constexpr double kResidualRel = 1e-12;          // an equation of motion's residual (or its start state), of the sum of |terms|
inline constexpr double kModalSumTwoPathsRel = 1e-14;  // one modal sum evaluated by two functions
inline constexpr double kEigenSolverRel = 1e-12;       // closed-form eigenvalues against a numerical eigen-solver
inline constexpr double kModalMassRel = 1e-12;         // modal and effective mass identities, of the mass
inline constexpr double kChainRk4LiftAbs = 1e-12;      // [m] RK4 at 1/400 of the top mode's period against the modal solution (measured 1e-13)
inline constexpr double kChainRk4ForceAbs = 2e-7;      // [N] its end forces (measured 2e-8)
inline constexpr double kSlowSurgeRel = 1e-3;          // quasi-static chain at w = w_1 / 100: surge (w / w_1)^2 from the start, of k e
inline constexpr double kPrinted13DigitsRel = 1e-12;   // a value against its 13 printed digits
inline constexpr double kNearResonanceRel = 1e-6;      // the 1 / (K - m w^2) amplitude 1e-6 off resonance: cancellation in K - m w^2
inline constexpr double kSwitchContinuityRel = 1e-12;  // x, x' across a contact switch, of their peaks
inline constexpr double kAccelJumpRel = 1e-9;          // the jump of x'' at a switch, of c |d'| / m
inline constexpr double kValveRk4LiftAbs = 1e-9;       // [m] RK4 at 10 ns through the contact switches (first order there; measured 4.4e-10)
inline constexpr double kValveRk4SpeedAbs = 1e-4;      // [m/s] its speed (measured 3.8e-5)
inline constexpr double kRk4EventSteps = 2.0;          // [steps] an RK4 contact event against the exact switch
inline constexpr double kEnergyBalanceRel = 1e-12;     // the cam's work against the energy balance, of the gross work (measured 4e-16)
inline constexpr double kScanHalvingRel = 1e-9;        // event times, landing speed and bounce height under halving the scan step
inline constexpr double kLandingSpeedRel = 5e-4;       // the valve's landing speed against the cam face's (three fixed-point steps; measured 1.4e-4)
inline constexpr double kPrinted6DigitsRel = 1e-5;     // a value against its 6 printed digits
inline constexpr double kQuasiStaticDeflectionRel = 5e-4;  // peak lift against the quasi-static contact deflection, of it (measured 8e-5)

// lift laws and envelope synthesis (tests/synthesis)
inline constexpr double kLawClosedFormRel = 1e-12;   // a lift law against its published formula, of the peak |d^k|
inline constexpr double kNortonDecimalsAbs = 1e-6;   // [unit rise] against Norton's 8-digit decimal coefficients
inline constexpr double kPublishedCoefAbs = 6e-5;    // against a peak coefficient published to 4-5 digits
inline constexpr double kPrinted3DecimalsAbs = 1e-3; // against a value published to 3 decimals
inline constexpr double kSampledPeakRel = 1e-9;      // a peak sampled on a 2e5-point grid against its exact value
inline constexpr double kLawFdRel = 1e-8;            // analytic against 8th-order central differences at 0.02 deg, of the peak
inline constexpr double kLawIdentityRel = 1e-12;     // identities of a law that hold to rounding, of the stated scale
inline constexpr double kCoefTwoFormsRel = 1e-14;    // a peak coefficient against its closed form written out again
inline constexpr double kClosureChangeAbs = 1e-15;   // a B-spline shape that already closes needs no closure change
inline constexpr double kClosureChange4567Abs = 1e-14;  // the same for the 4-5-6-7 shape (larger coefficients)
inline constexpr double kClosureRatioRel = 1e-10;    // the closure change per weight, equal for every coefficient
inline constexpr double kJoinSlopeSlackRel = 0.01;   // a continuous d^k across a join: 2 eps max|d^(k+1)|, 1 % slack
inline constexpr double kJoinRoundOffRel = 1e-13;    // and round-off, of max |d^k|
inline constexpr double kJerkJoinRel = 1e-6;         // a jerk that the laws make continuous (or zero) at a join, of the peak jerk
inline constexpr double kRampEndLiftAbs = 1e-12;     // [mm] lift 1e-6 deg before the end of the closing ramp
inline constexpr double kRampEndVelocityAbs = 1e-9;  // [mm/deg] its velocity there
inline constexpr double kPeakLiftRel = 1e-14;        // the lift at the peak angle against the max lift
inline constexpr double kPeakVelocityAbs = 1e-14;    // [mm/deg] the velocity there
inline constexpr double kPeriodShiftAbs = 1e-12;     // the event one or two revolutions on (the angle rounds by ~1e-13 deg)
inline constexpr double kNortonDurationAbs = 2e-4;   // [deg] a duration against a bisection on Norton's decimals (~1e-7 in lift)
inline constexpr double kSummaryPeakAccRel = 1e-6;   // a summary's sampled peak acceleration against the laws' closed form
inline constexpr double kDiscProfileAbs = 1e-8;      // [mm] a synthesized disc's radius against the exact disc
inline constexpr double kDiscCurvatureRel = 1e-6;    // its smallest radius of curvature against R
inline constexpr double kDiscExtremeRadiusRel = 1e-9;  // its base and max radius against R - e, R + e
inline constexpr double kDiscRoundTripAbs = 1e-8;    // [mm] forward lift of the synthesized disc against the target
inline constexpr double kRoundTripAbs = 1e-6;        // [mm or rad] forward motion of a synthesized cam against its target
inline constexpr double kBenchRecomputedRel = 1e-12;  // a camopt bench error recomputed in the test from the CLI's CSV files (shortest round-trip numbers, the same arithmetic)
inline constexpr double kPrintedPressureAngleAbs = 1e-3;  // [deg] a peak pressure angle against its 4-decimal value
inline constexpr double kFaceOffsetAbs = 1e-6;       // [mm] the contact's extreme offsets along a flat face
inline constexpr double kOwnLobeAbs = 1e-5;          // [mm] a synthesized lobe against the 1-deg table it came from, via a 0.5-deg lift spline
inline constexpr double kSwingInputLobeAbs = 1e-4;   // [mm] the CVVL's input lobe back from the swing-cam motion
inline constexpr double kBridgedLobeAbs = 5e-3;      // [mm] the same where the lever leaves its rest (the lift barely moves)
inline constexpr double kBaseCircleAbs = 1e-6;       // [mm] a synthesized base circle against the lobe's
inline constexpr double kTabledEccentricAbs = 1e-8;  // [mm] an analytic against a 2-deg tabled eccentric (spline error 2e-10)
inline constexpr double kGrindingLiftAbs = 1e-9;     // [mm] a grinding table against its closed form
inline constexpr double kLeverPoseAbs = 1e-10;       // [mm or rad] the lever path's pose against whole solves (each to ~1e-12)
inline constexpr double kLeverRateRel = 1e-8;        // its derivatives, of their peak

// the optimiser's models (tests/opt)
inline constexpr double kOptPressureAngleAbs = 1e-8;  // [rad] the optimiser's closed-form pressure angle against the kinematic solver's
inline constexpr double kOptRollerSpeedAbs = 1e-8;    // [mm/rad] its roller speed, the same
inline constexpr double kOptContactRel = 1e-7;        // its sliding [mm/rad], entrainment and cam curvature [1/mm], of max(1, |reference|)
inline constexpr double kOptContactFdRel = 1e-5;      // its gradients against central differences at 1e-4: truncation h^2 f''' / 6
inline constexpr double kOptContactFdAbs = 1e-7;      // the same for a gradient of ~0, times 1 + |the quantity|
inline constexpr double kOptLoadRel = 1e-9;           // [N] its loads by virtual work against the rigid model's multipliers, of max(1, |the first spring's force|)
inline constexpr double kOptStaticsFdAbs = 1e-6;      // [N per unit] their gradients against central differences (h = 1e-5 mm, 1e-4, 1e-3): static load
inline constexpr double kOptDampingFdAbs = 1e-9;      // the same: damping load (linear in the velocity)
inline constexpr double kOptInertiaFdAbs = 1e-10;     // the same: inertia load (linear in the acceleration)
inline constexpr double kSameDiagnosisRel = 1e-6;     // a best achievable value after different solvers: the same solves from the same start, up to the warm-started inversions' round-off
inline constexpr double kSameOptimumRel = 1e-7;       // the objective of two solves of one problem, of max(1, |objective|): both reach the KKT point to 1e-9, room for the active set's conditioning
inline constexpr double kSameInfeasiblePointRel = 1e-9;  // the worst violation of two solves that end at the same full-row point
inline constexpr double kOptLiftJoinAbs[3] = {1e-9, 1e-9, 1e-7};  // [mm, mm/deg, mm/deg^2] the b-spline lift 1e-9 deg either side of a c2 join
inline constexpr double kOptOpeningRampAbs = 1e-12;   // [mm] the opening ramp's height, set directly
inline constexpr double kOptClosingRampAbs = 1e-10;   // [mm] the closing ramp's height, reached through the closure solve
inline constexpr double kOptLiftFdAbs = 1e-8;         // [per deg] a b-spline lift's derivative against central differences at 1e-4 deg
inline constexpr double kSplineSpaceFitAbs = 1e-10;   // a least-squares fit of a spline (a lift) in its own space against its coefficients: solve round-off
inline constexpr double kOptRowFdRel = 1e-5;          // a constraint row's jacobian against central differences at 1e-6 (warm-started inversions in the rows)
inline constexpr double kOptRowFdAbs = 1e-6;          // the same for an entry of ~0
inline constexpr double kOptLoadRowFdAbs = 2e-6;      // the same for the load rows (spring margin, separation, film: one more solve each)
inline constexpr double kOptObjectiveFdRel = 1e-6;    // the objective's gradient against central differences at 1e-6
inline constexpr double kOptObjectiveFdAbs = 1e-8;    // the same for a gradient of ~0
inline constexpr double kOptHertzFdRel = 1e-6;        // the flat-face hertz row's jacobian against central differences at 1e-6
inline constexpr double kOptHertzFdAbs = 1e-7;        // the same for an entry of ~0
inline constexpr double kOptHessianFdRel = 1e-8;      // a target fit's hessian against central differences of its gradient at 1e-4 (exact: the lift is linear), of the largest entry
inline constexpr double kOptHertzRowRel = 1e-9;       // the hertz row against (p0^2 - s^2) R / (s^2 R_ref) from its own p0 and R, of max(1, |g|)
inline constexpr double kOptActiveRowAbs = 1e-6;      // a normalised row active at the optimum: the solvers' feasibility tolerance
inline constexpr double kOptActiveLimitRel = 1e-5;    // a linear limit the optimum presses on, of the limit
inline constexpr double kOptClosureAbs = 1e-8;        // [mm, mm/deg, ...] the closure equalities at the optimum
inline constexpr double kFitOptimumLiftAbs = 1e-6;    // [mm] a target fit's optimum against its kkt solution (mma stops 6e-7 to 8.3e-7 mm from it)
inline constexpr double kSynthesizedSeparationRel = 5e-3;  // the rigid model's separation speed of the synthesized cam against the active limit: rows on a 0.5-deg grid, the force dips between
inline constexpr double kSynthesizedHertzRel = 2e-3;  // the hertz row against p0 of the synthesized cam (a quintic spline through the lift every 0.25 deg)
inline constexpr double kSwingTableLiftAbs = 2e-6;    // [mm] the swing-cam lift model against the kinematic solver on its 7200-point profile table
inline constexpr double kSwingTableAccAbs = 1e-6;     // [mm/deg^2] its acceleration, the same
inline constexpr double kDrawnDwellRadiusRel = 1e-6;  // a dwell radius against |Q - Rr| of the drawing
inline constexpr double kSwingSensitivityFdRel = 1e-7;  // the swing lift's coefficient sensitivities against central differences at 1e-5 mm, of the largest
inline constexpr double kSwingEnvelopeRel = 1e-6;     // the swing model's contact quantities against the envelope model's away from the reversal
inline constexpr double kSwingEnvelopePressureAngleAbs = 1e-7;  // [rad] its pressure angle, the same
inline constexpr double kSwingObjectiveFdAbs = 5e-5;  // the swing objective's gradient against central differences at 1e-4: 2 x its ~3e-9 noise / 1e-4
inline constexpr double kActiveLiftCapAbs = 1e-6;     // [mm] the peak lift against a lift cap active at the optimum

// synthesized profiles, target lifts and undercut windows (tests/synthesis)
inline constexpr double kReadBackProfileRel = 1e-12;  // a profile read back from its shortest round-trip CSV, of the peak: the same doubles, at most a reordered sum
inline constexpr double kSwingRoundTripAbs = 1e-4;    // [mm] forward lift of a synthesized swing cam against its target
inline constexpr double kCvvlOtherControlLiftAbs = 1e-3;  // [mm] the CVVL swing cam synthesized at full lift, its lift at other controls against the original's
inline constexpr double kVvldOtherControlLiftAbs = 5e-5;  // [mm] the same for the VVLD control arm (measured 2.9e-6 .. 1.7e-5; the original's 1-deg table ripples 1.3e-5)
inline constexpr double kValvetronicOtherControlLiftAbs = 2e-5;  // [mm] the same for the Valvetronic lever (measured 4.2e-6 .. 5.2e-6)
inline constexpr double kSwingCurvatureMedianAbs = 1e-8;  // reported against the quintic profile's curvature, x the smallest radius: the median point
inline constexpr double kSwingCurvature99Abs = 1e-3;  // the same at the 99th percentile (next to a join of two pieces the spline rounds a curvature step)
inline constexpr double kSwingMinRadiusRel = 1e-8;    // the reported smallest radius of curvature against 1 / the profile's largest curvature
inline constexpr double kSwingConcaveRadiusRel = 1e-4;  // the smallest concave radius, the same (the spline rounds the curvature by 2e-5 of it)
inline constexpr double kIdleArcAbs = 1e-5;           // [mm] a synthesized idle arc against its radius (measured 2.8e-6)
inline constexpr double kTracedRampAbs = 1e-6;        // [mm] a synthesized traced ramp against the design's 1-deg working curve (measured 2.4e-8)
inline constexpr double kSwingRestRadiusAbs = 1e-4;   // [mm] a swing cam's base radius against the rest radius (dwell or idle arc)
inline constexpr double kTargetRoundOffMoveAbs = 1e-8;  // [mm] a swing profile after a 1e-12 relative change of its target (measured 8.6e-11 .. 1.7e-9)
inline constexpr double kTargetContinuityRel = 1e-6;  // a target lift's f^(k), k <= 4, either side of a knot, of max |f^(k)| (plus the slope over the 1e-9 rad offset)
inline constexpr double kInterpolatedPeakLiftAbs = 1e-6;  // [mm] the peak of the 2-deg interpolated cycloidal rise-fall against its 9 mm
inline constexpr double kInterpolatedPeakAngleAbs = 1e-3;  // [deg] its angle against 120 deg
inline constexpr double kBetweenSitesAbs = 1e-4;      // [mm] the same interpolant between its 2-deg sites against the law (c2, jerk steps)
inline constexpr double kSmoothSlopeStepRatioAbs = 1e-3;  // the largest slope step of a smooth 0.25-deg table, of the lift's mean slope
inline constexpr double kTakeUpSlopeRel = 0.05;       // the lashed table's slope step against the law's slope at the take-up (one 0.25-deg row)
inline constexpr double kTakeUpAngleAbs = 0.5;        // [deg] its angle against the take-up angle
inline constexpr double kSlopeStepRatioRel = 1e-3;    // the reported slope step ratio against the step / the mean slope
inline constexpr double kTablePeakLiftAbs = 1e-3;     // [mm] a real table's interpolated peak against its largest row (it may only rise above it)
inline constexpr double kTablePeakAngleAbs = 0.5;     // [deg] its angle against that row's
inline constexpr double kSeamTablePeakLiftAbs = 0.01; // [mm] the ICESym table's interpolated peak against 14.195 mm read off the table
inline constexpr double kSeamTablePeakAngleAbs = 1.0; // [deg] its angle against 52.5 deg
inline constexpr double kSmoothedRmsAbs = 0.005;      // [mm] rms of a smoothed noisy table against the clean law: sigma / 2 (expected sigma sqrt(m / n) = 0.0035, sigma = 0.01 mm)
inline constexpr double kSmoothedLawAbs = 0.02;       // [mm] its worst point: 2 sigma (<= 0.0147 mm over 200 seeds)
inline constexpr double kSmoothedPeakLiftAbs = 0.01;  // [mm] its peak against 9 mm: 1 sigma
inline constexpr double kSmoothedPeakAngleAbs = 2.0;  // [deg] its angle against 120 deg
inline constexpr double kBSplineConversionAbs = 1e-6; // [mm] the smoothed target (a periodic quintic) against the fitted b-spline it converts
inline constexpr double kBSplineFdRel = 1e-5;         // a b-spline's derivatives against central differences at 1e-3 deg, of 1 + |f^(k)|
inline constexpr double kWindowEndAbs = 0.01;         // [deg] a refined undercut window end, printed to 3 decimals, against the closed form's root
inline constexpr double kHermiteRootAbs = 1e-4;       // [deg] a window end on the cubic hermite of a 10-deg sampled cos against its root (measured 2.7e-6; the chord is 4.3e-3 off)
inline constexpr double kChordRootAbs = 1e-9;         // [deg] a window end on the chord of a 10-deg sampled cos against the chord's root: round-off
inline constexpr double kPeakAtSiteRel = 1e-9;        // the peak of a lift sampled at 0.25 deg whose law peaks at a site, against the law's peak

// dynamics and CLI
inline constexpr double kCompliantStiffForceAbs = 2e-5 * 563.0;  // [N] compliant (x10 stiffness) against rigid contact force: first order in 1/k, 2e-5 of the 563 N peak
inline constexpr double kStiffLinkForceRel = 1e-2;  // a 1e6 N/mm link's force against the rigid one: the link's stretch, of the peak
inline constexpr double kSeparationEventAbs = 3.0;  // [deg] a compliant contact opening against the rigid model's first tension on a 1-deg grid
inline constexpr double kPrinted5DigitsRel = 1e-4;   // a value against its hand computation printed to 5 significant digits
inline constexpr double kPrinted9DigitsRel = 1e-8;   // the same, printed to 9 significant digits
inline constexpr double kPrinted10DigitsRel = 1e-9;  // the same, printed to 10 significant digits
inline constexpr double kRearrangedLawRel = 1e-12;   // one law written two ways, in other units or inverted by a Newton solve to round-off
inline constexpr double kPowerLawRel = 1e-13;        // a power-law formula (pow of products) evaluated along two paths
inline constexpr double kHertzFixedPointRel = 1e-9;  // the Hertz line law by 22 fixed-point iterations (contraction < 0.1) from delta / 10
inline constexpr double kCentral2Step1e6Rel = 1e-7;  // 2-point central difference at a relative step of 1e-6: round-off ~1e-10 through a solve
inline constexpr double kRestitutionSecondOrder = 1.1;  // Hunt-Crossley rebound against e = 1 - alpha v: the remainder, in units of (alpha v)^2
inline constexpr double kRigidForceRel = 1e-7;       // rigid forces and torques against a balance written in the test: kinematic derivatives (1e-7) and one LU solve, of the peak
inline constexpr double kZeroReactionAbs = 1e-4;     // [N] a reaction that is zero by symmetry: round-off of forces ~1e3 N
inline constexpr double kSeparationRpmRel = 1e-9;    // the separation speed against the smallest root written in the test on the same grid
inline constexpr double kSeparationForceRel = 1e-9;  // the least contact force at the separation speed, of the preload (or the peak force)
inline constexpr double kSeparationRefinedAngleAbs = 1e-4;  // [deg] the angle of the least separation speed refined between grid points against its closed form: the minimiser stops at ~1e-8 of the bracket, the quadratic minimum fixes the angle to ~sqrt(1e-16)
inline constexpr double kSpringMarginRel = 1e-12;    // the spring margin of one spring loading one contact against its contact force
inline constexpr double kQuadraticInSpeedRel = 1e-12;  // a force at a third speed against A + B w^2 from two others: cancellation in B
inline constexpr double kBaseCircleForceRel = 1e-9;  // a contact force on the base circle at two angles: solve round-off, no sliding
inline constexpr double kCycleWorkRel = 1e-6;        // net work of a conservative cycle (trapezoidal at 0.25 deg), of the work of |torque|
inline constexpr double kHeldEndSurgeRel = 2e-5;     // surge frequencies with the valve end held by a 1e3 x stiff contact against the fixed-fixed chain
inline constexpr double kLumpedCoil40Rel = 3e-4;     // f1 of 40 lumped masses against the continuous coil's 1/2 sqrt(k/m): ~(pi/82)^2/6
inline constexpr double kTwoMassLowModeRel = 1e-4;   // the train's lower mode against the two-mass model of the same data
inline constexpr double kTwoMassHighModeRel = 1e-3;  // its higher mode, which the two-mass split of the pushrod mass moves more
inline constexpr double kHandbookRoundedDataRel = 5e-3;  // a mode against the handbook's, recomputed from its rounded masses and stiffnesses
inline constexpr double kTwoMassClosedFormRel = 1e-9;    // the train frequency against the two-mass closed form of the same stiffnesses
inline constexpr double kRk4LiftRel = 1e-6;          // flexible lift (rtol 1e-10) against RK4 at 1.25e-7..2.5e-7 s through impacts, of the peak
inline constexpr double kRk4ForceRel = 1e-4;         // its contact force, of the peak: the Hertz law's stiffness amplifies the lift error
inline constexpr double kPowerBalanceRel = 1e-4;     // a flexible run's work in against energy change and losses (rtol 1e-9), of the largest drive work
inline constexpr double kLowSpeedForceRel = 1e-2;    // flexible contact forces at 500-2000 rpm against mode (a): left-over vibration, of the peak
inline constexpr double kQuasiStaticDeficitAbs = 1e-2;  // [N] flexible contact force at 10-50 rpm against mode (a) less k_s delta (measured 3 mN)
inline constexpr double kDeficitPeakRel = 0.1;       // the largest |flexible - mode (a)| against the largest k_s delta: they peak at nearby angles
inline constexpr double kPeriodicLiftAbs = 1e-6;     // [mm] a run stopped at its periodic steady state against the full run: its start-state tolerance
inline constexpr double kPeriodicForceAbs = 0.3;     // [N] the same for the contact force: 1e-6 mm x contact stiffness ~3e5 N/mm
inline constexpr double kLashKinkShiftAbs = 1.0;     // [deg] a lash transition against the path's kink: the static deflection over the take-up slope
inline constexpr double kNewtonMatrixFdRel = 1e-6;   // Newton matrices K, D against central differences of the forces (~1e-8), of the largest entry
inline constexpr double kJacobianPathRel = 1e-8;     // lift with CVODE's differenced Jacobian against the analytic one (rtol 1e-9), of the peak
inline constexpr double kPathTableAbs = 1e-8;        // [mm] the kinematic path from its 0.25-deg Catmull-Rom table against the closed form (5e-9)
inline constexpr double kValveEventAngleAbs = 0.01;  // [deg] a contact event against the exact piecewise-analytic valve
inline constexpr double kSeatSpeedAbs = 1e-3;        // [m/s] a seat impact speed against the exact valve
inline constexpr double kValveLiftExactAbs = 1e-3;   // [mm] the lift against the exact valve at default tolerances, through five bounces
inline constexpr double kCoilForceAbs = 1e-2;        // [N] coil end forces against exact modal superposition (measured 3e-4 N at rtol 1e-8)
inline constexpr double kOutputAngleAbs = 1e-9;      // [deg] an output angle against start + i step
inline constexpr double kAtRestAbs = 1e-12;          // [mm/s] the speed of a body started at rest
inline constexpr double kPeakLiftDeflectionAbs = 0.05;  // [mm] a flexible run's peak lift against the kinematic peak: the train's deflection
inline constexpr double kLiftLossShareRel = 0.05;    // a dynamic run's peak lift against the kinematic one: the train's deflection, a few percent
inline constexpr double kCsvVelocityFdRel = 2e-3;    // a velocity column against central differences of the lift column (0.02 deg), of the peak
inline constexpr double kCsvAccelerationFdRel = 2e-2;  // an acceleration column against central differences of the velocity column, of the peak
inline constexpr double kCsvInertiaFdRel = 1e-4;     // an inertia column against -m a by second differences of the lift at 1 deg (2.5e-5 of a harmonic)
inline constexpr double kCsvContactRel = 1e-11;      // contact columns against closed forms of the CSV's kinematics (shortest round-trip), of the peak
inline constexpr double kCsvDerivedRel = 1e-9;       // a column or summary value against the same quantity recomputed from other columns
inline constexpr double kRevolutionClosureAbs = 1e-9;  // [deg or mm] an output back at its drawing value after a revolution
inline constexpr double kPrintedAngleSineAbs = 1e-3;   // the sine of an angle given to 0.1 deg (cos x 0.05 deg <= 8.7e-4)
inline constexpr double kRefinedSummaryRel = 1e-9;   // a refined summary value (peak, duration, span, area) against its closed form, of its scale
inline constexpr double kRefinedExtremeAngleAbs = 1e-5;  // [deg] the refined angle of a velocity or acceleration extreme
inline constexpr double kHermitePolyRel = 1e-12;     // the order-3 Hermite interpolant reproducing a degree-7 polynomial, of max(1, |p^(k)|)
inline constexpr double kHermiteIntegralAbs = 1e-13;  // its exact integral against the antiderivative's difference
inline constexpr double kHermiteStationaryAbs = 1e-12;  // [rad] the order-3 interpolant's stationary point of cos at pi (measured 5e-13)
inline constexpr double kRadiusSampledRel = 1e-8;    // a refined radius of curvature against 200000 samples of the profile: rho'' (h / 2)^2 / 2 < 1e-9
inline constexpr double kDocumentedRadiusAbs = 0.05;  // [mm] a radius against a design's documented figure given to 0.1 mm
inline constexpr double kIntervalSumAbs = 360 * 1e-9;  // [deg] interval widths summed against their reported total
inline constexpr double kChainEigenRel = 1e-10;      // a spring chain's frequencies from the eigen-solve against the chain's closed form
inline constexpr double kModeOrthonormalAbs = 1e-8;  // M-products of two mode shapes read from the CSV against the identity
inline constexpr double kTwoSolvePathsRel = 1e-9;    // a kinematic lift against a Newton iteration on the same geometry written in the test
inline constexpr double kLawLiftRel = 1e-12;         // a lift law's peak against --lift: round-off of its normalisation
inline constexpr double kLawLiftAnyRel = 1e-9;       // the same for every law (B-spline and polydyne laws are normalised through a solve)
inline constexpr double kRampVelocityRel = 1e-10;    // a ramp's constant velocity against Hr / (Lr (1 - b/2))
inline constexpr double kCrankBasisAbs = 1e-12;      // a crank-basis column against the cam-basis one scaled by 2^-k
inline constexpr double kCrankBasisRel = 1e-12;      // the same, of the value
inline constexpr double kVerifyPressureAngleAbs = 0.05;  // [deg] the verifying solver's max pressure angle against the optimiser's constraint value
inline constexpr double kBestAchievableLiftAbs = 1e-3;   // [mm] the best peak lift an optimisation reaches against its measured value
inline constexpr double kVerifyPeakLiftAbs = 5e-5;   // [mm] the flexible verification's 0.5-deg grid peak of the kinematic lift against the refined one (measured 2.1e-5)
inline constexpr double kTwoMassTurnedRockerRel = 1e-3;  // the train's modes at 10 cam deg against the two-mass model of the drawing's geometry
}  // namespace tol

}  // namespace camopt::test
