"""Reference vehicle simulator (grip issue 5): two-track vehicle model with
roll and wheel spin, Magic Formula tyres from grip_tools.reference.mf, sensor models,
CAN logs and standard manoeuvres. See docs/simulator.md.

Main entry points:
  vehicles.passenger(), vehicles.av21()       parameter sets
  model.Effects, model.Road, model.Scenario   what to simulate
  model.simulate(vehicle, scenario, effects)  -> model.Result
  manoeuvres.build(name, vehicle, surface)    standard manoeuvres
  sensors.SensorConfig, sensors.measure(...)  ESC sensor models
  canlog.write_candump / read_candump / decode_log
"""
