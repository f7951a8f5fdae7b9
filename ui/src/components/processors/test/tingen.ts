// GET .../fmus/Tingen.fmu for the Tingen FMU built from examples/tingen/fmu (inspect_fmu).
import type { Fmu } from "../../../api/processors";

export const tingenFmu: Fmu = {
 "name": "Tingen.fmu",
 "sha256": "0000000000000000000000000000000000000000000000000000000000000000",
 "size": 21694,
 "uploaded_ns": 1767225600000000000,
 "fmi_version": "2.0",
 "model_name": "tingen",
 "guid": "{6f1c2b7e-3d4a-4e59-8b20-71a9c4d5e8f3}",
 "description": "Tingen cantilever rig (NTNU): first bending mode of a steel cantilever with a tip mass under a horizontal tip force",
 "generation_tool": "twinlink (hand-written C, see sources/tingen.c)",
 "platform": "linux64",
 "co_simulation": true,
 "model_exchange": true,
 "has_binary": true,
 "interfaces": [
  {
   "kind": "CoSimulation",
   "model_identifier": "tingen",
   "has_binary": true,
   "needs_completed_integrator_step": false,
   "can_handle_variable_step": true
  },
  {
   "kind": "ModelExchange",
   "model_identifier": "tingen",
   "has_binary": true,
   "needs_completed_integrator_step": false,
   "can_handle_variable_step": true
  }
 ],
 "default_experiment": {
  "start": 0.0,
  "stop": 10.0,
  "step": 0.001,
  "tolerance": null
 },
 "number_of_continuous_states": 2,
 "number_of_event_indicators": 0,
 "variables": [
  {"name": "F", "value_reference": 1, "causality": "input", "variability": "continuous", "type": "Real", "initial": "exact", "unit": "N", "start": 0.0, "min": -50.0, "max": 50.0, "description": "Horizontal force at the tip", "shape": []},
  {"name": "theta", "value_reference": 2, "causality": "output", "variability": "continuous", "type": "Real", "initial": "calculated", "unit": "rad", "start": null, "min": null, "max": null, "description": "Tip angle, 3 w / (2 L)", "shape": []},
  {"name": "sigma", "value_reference": 3, "causality": "output", "variability": "continuous", "type": "Real", "initial": "calculated", "unit": "Pa", "start": null, "min": null, "max": null, "description": "Bending stress in the outer fibre at the root, k w L c_fiber / I", "shape": []},
  {"name": "w", "value_reference": 4, "causality": "output", "variability": "continuous", "type": "Real", "initial": "exact", "unit": "m", "start": 0.0, "min": null, "max": null, "description": "Tip deflection (continuous state)", "shape": []},
  {"name": "v", "value_reference": 5, "causality": "local", "variability": "continuous", "type": "Real", "initial": "exact", "unit": "m/s", "start": 0.0, "min": null, "max": null, "description": "Tip velocity (continuous state)", "shape": []},
  {"name": "der(w)", "value_reference": 6, "causality": "local", "variability": "continuous", "type": "Real", "initial": "calculated", "unit": "m/s", "start": null, "min": null, "max": null, "description": "Derivative of the tip deflection", "shape": []},
  {"name": "der(v)", "value_reference": 7, "causality": "local", "variability": "continuous", "type": "Real", "initial": "calculated", "unit": "m/s2", "start": null, "min": null, "max": null, "description": "Tip acceleration, (F - c v - k w) / m_eff", "shape": []},
  {"name": "L", "value_reference": 10, "causality": "parameter", "variability": "fixed", "type": "Real", "initial": "exact", "unit": "m", "start": 0.3, "min": 0.01, "max": 10.0, "description": "Free length of the beam (thesis table 3.1)", "shape": []},
  {"name": "I", "value_reference": 11, "causality": "parameter", "variability": "fixed", "type": "Real", "initial": "exact", "unit": "m4", "start": 2.1e-12, "min": 1e-16, "max": 0.001, "description": "Area moment of inertia about the bending axis (thesis table 3.1: 2.1 mm^4)", "shape": []},
  {"name": "E", "value_reference": 12, "causality": "parameter", "variability": "fixed", "type": "Real", "initial": "exact", "unit": "Pa", "start": 210000000000.0, "min": 1000000.0, "max": 1000000000000.0, "description": "Young's modulus (thesis table 3.1: 210000 N/mm^2)", "shape": []},
  {"name": "tip_mass", "value_reference": 13, "causality": "parameter", "variability": "fixed", "type": "Real", "initial": "exact", "unit": "kg", "start": 0.0, "min": 0.0, "max": 100.0, "description": "Mass at the tip. The thesis's input force is the whole tip load computed from the measured angle, tip mass included, so the demo leaves it at 0", "shape": []},
  {"name": "beam_mass_per_length", "value_reference": 14, "causality": "parameter", "variability": "fixed", "type": "Real", "initial": "exact", "unit": "kg/m", "start": 0.196, "min": 0.0, "max": 100.0, "description": "Mass of the beam per metre (a 25 mm x 1 mm steel strip)", "shape": []},
  {"name": "zeta", "value_reference": 15, "causality": "parameter", "variability": "tunable", "type": "Real", "initial": "exact", "unit": null, "start": 0.02, "min": 0.0, "max": 10.0, "description": "Damping ratio of the first bending mode", "shape": []},
  {"name": "c_fiber", "value_reference": 16, "causality": "parameter", "variability": "fixed", "type": "Real", "initial": "exact", "unit": "m", "start": 0.0005, "min": 0.0, "max": 0.1, "description": "Distance of the outer fibre from the neutral axis (half the thickness)", "shape": []}
 ],
};
