"""Independent judge of the onboard estimator (docs/independent-judge.md).

The vehicle is CommonRoad's multi-body model (the `commonroad-vehicle-models`
package, module `vehiclemodels`: 29 states, roll, pitch, unsprung masses,
suspension, its own Magic Formula tires), used as a dependency, never
copied. Nothing here shares code or parameters with grip_tools.sim (the
in-family simulator) or with the estimator.

  mb          the driver: parameter sets, surfaces, road bank / grade as
              external accelerations, fixed-step RK4, per-wheel force truth
  manoeuvres  the manoeuvres and the driver robot (speed PI, steering servo,
              path following, ABS)
  sensors     ESC sensor cluster from the model's states: wheel speeds,
              steering-wheel angle, gyro, accelerometers (specific force)
  judge       the estimator configured as an OEM would, the C builds over
              the sensors, metrics, baselines, tables and plots
              (grip est-eval --independent)
"""
