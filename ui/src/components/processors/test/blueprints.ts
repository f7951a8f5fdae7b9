// Blueprints as the server describes them (GET /api/v1/blueprints/{name}), dumped from the
// built-in blueprints with describe_blueprint(): the parameter schemas are pydantic's own.
import type { Blueprint } from "../../../api/processors";

export const triggerBlueprint: Blueprint = {
 "name": "trigger",
 "title": "Alarm trigger (threshold or rate of change)",
 "description": "Alarm trigger (threshold or rate of change)\n\n    Watches one signal. threshold mode: raises when the value goes above `high` (or below\n    `low`, direction below) and clears only when it is back past `clear_at` (hysteresis).\n    rate mode: raises when |d signal / dt| (between consecutive samples) exceeds `rate_limit`\n    per second and clears when it is below `rate_limit * clear_fraction`. With\n    `min_duration_s`, the condition must hold that long before the alarm is raised. Raising\n    gives an `alarm` event (and `command`, if set), clearing an `alarm_cleared` event (and\n    `clear_command`). The output `{signal}.alarm` is 1 while raised, 0 otherwise.",
 "keeps_state": true,
 "params_schema": {
  "$defs": {
   "CommandSpec": {
    "additionalProperties": false,
    "properties": {
     "name": {
      "description": "The command's name.",
      "minLength": 1,
      "title": "Name",
      "type": "string"
     },
     "params": {
      "additionalProperties": true,
      "description": "The command's parameters.",
      "title": "Params",
      "type": "object"
     },
     "device": {
      "anyOf": [
       {
        "type": "string"
       },
       {
        "type": "null"
       }
      ],
      "default": null,
      "description": "The device to send it to; empty: the twin's only (or first) device.",
      "title": "Device"
     }
    },
    "required": [
     "name"
    ],
    "title": "CommandSpec",
    "type": "object"
   }
  },
  "additionalProperties": false,
  "properties": {
   "signal": {
    "description": "The signal watched.",
    "title": "Signal",
    "type": "string"
   },
   "mode": {
    "default": "threshold",
    "description": "threshold: the value crosses a level; rate: the value changes faster than rate_limit per second (either way).",
    "enum": [
     "threshold",
     "rate"
    ],
    "title": "Mode",
    "type": "string"
   },
   "direction": {
    "default": "above",
    "description": "threshold mode: raise when the value is above high or below low.",
    "enum": [
     "above",
     "below"
    ],
    "title": "Direction",
    "type": "string"
   },
   "high": {
    "anyOf": [
     {
      "type": "number"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "Raise when the value is above this (above).",
    "title": "High"
   },
   "low": {
    "anyOf": [
     {
      "type": "number"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "Raise when the value is below this (below).",
    "title": "Low"
   },
   "clear_at": {
    "anyOf": [
     {
      "type": "number"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "Hysteresis: clear only when the value is back below this (above) or above this (below); empty: the raise level itself.",
    "title": "Clear At"
   },
   "rate_limit": {
    "anyOf": [
     {
      "exclusiveMinimum": 0,
      "type": "number"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "rate mode: raise when |d signal / dt| exceeds this, per second.",
    "title": "Rate Limit"
   },
   "clear_fraction": {
    "default": 0.8,
    "description": "rate mode: clear when |d signal / dt| is below rate_limit times this.",
    "exclusiveMinimum": 0,
    "maximum": 1,
    "title": "Clear Fraction",
    "type": "number"
   },
   "min_duration_s": {
    "default": 0.0,
    "description": "Raise only once the condition has held this long, in seconds.",
    "minimum": 0,
    "title": "Min Duration S",
    "type": "number"
   },
   "command": {
    "anyOf": [
     {
      "$ref": "#/$defs/CommandSpec"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "A command to send on raising."
   },
   "clear_command": {
    "anyOf": [
     {
      "$ref": "#/$defs/CommandSpec"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "A command to send on clearing."
   },
   "output": {
    "default": "samples",
    "description": "samples: `{signal}.alarm` (1 raised, 0 not) at every sample; changes: at the first sample and when it changes.",
    "enum": [
     "samples",
     "changes"
    ],
    "title": "Output",
    "type": "string"
   }
  },
  "required": [
   "signal"
  ],
  "title": "TriggerParams",
  "type": "object"
 },
 "source": "installed"
};

export const windowBlueprint: Blueprint = {
 "name": "window",
 "title": "Moving-window aggregates",
 "description": "Moving-window aggregates\n\n    Mean, RMS, min, max, peak-to-peak, standard deviation and count of each signal over a\n    moving window of time or of samples, at every sample or every `hop_s` seconds. Missing\n    values are ignored; an empty window gives NaN (count 0). Outputs are `{signal}.{function}`.",
 "keeps_state": true,
 "params_schema": {
  "additionalProperties": false,
  "properties": {
   "signals": {
    "description": "The signals to aggregate.",
    "items": {
     "type": "string"
    },
    "minItems": 1,
    "title": "Signals",
    "type": "array"
   },
   "functions": {
    "description": "Aggregates to compute: mean, rms (root mean square), min, max, p2p (peak to peak, max - min), std (population standard deviation) and count (number of values in the window). Each gives the output `{signal}.{function}`.",
    "items": {
     "enum": [
      "mean",
      "rms",
      "min",
      "max",
      "p2p",
      "std",
      "count"
     ],
     "type": "string"
    },
    "minItems": 1,
    "title": "Functions",
    "type": "array"
   },
   "window_s": {
    "anyOf": [
     {
      "exclusiveMinimum": 0,
      "type": "number"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "Window length in seconds: the window ending at time t holds the values with t - window_s < time <= t. Set this or window_samples.",
    "title": "Window S"
   },
   "window_samples": {
    "anyOf": [
     {
      "maximum": 10000000,
      "minimum": 1,
      "type": "integer"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "Window length in samples: the window holds the signal's latest this many values. Set this or window_s.",
    "title": "Window Samples"
   },
   "hop_s": {
    "default": 0.0,
    "description": "Output interval in seconds. 0: an output at every sample (rolling). Otherwise one output per interval that had samples, at its end (a multiple of hop_s since the epoch), made when the first sample after it arrives.",
    "minimum": 0,
    "title": "Hop S",
    "type": "number"
   }
  },
  "required": [
   "signals"
  ],
  "title": "WindowParams",
  "type": "object"
 },
 "source": "installed"
};

export const fmuBlueprint: Blueprint = {
 "name": "fmu",
 "title": "FMU",
 "description": "Runs an FMU (FMI 2.0 or 3.0, co-simulation or model exchange) on the input signals.",
 "keeps_state": true,
 "params_schema": {
  "additionalProperties": false,
  "properties": {
   "fmu": {
    "description": "File name of an uploaded FMU (no folders).",
    "title": "Fmu",
    "type": "string"
   },
   "inputs": {
    "anyOf": [
     {
      "items": {
       "type": "string"
      },
      "type": "array"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "FMU inputs to feed (numbers, Boolean, Enumeration); default: all.",
    "title": "Inputs"
   },
   "outputs": {
    "anyOf": [
     {
      "items": {
       "type": "string"
      },
      "type": "array"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "FMU variables to output; default: all numeric outputs.",
    "title": "Outputs"
   },
   "parameters": {
    "additionalProperties": {
     "anyOf": [
      {
       "type": "number"
      },
      {
       "type": "integer"
      },
      {
       "type": "boolean"
      },
      {
       "type": "string"
      }
     ]
    },
    "description": "Values set before initialisation: parameters and start values.",
    "title": "Parameters",
    "type": "object"
   },
   "step": {
    "default": "samples",
    "description": "Step to each input sample's time, or on a fixed grid.",
    "enum": [
     "samples",
     "fixed"
    ],
    "title": "Step",
    "type": "string"
   },
   "step_size_s": {
    "anyOf": [
     {
      "exclusiveMinimum": 0,
      "type": "number"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "The grid step in seconds (required for step = fixed).",
    "title": "Step Size S"
   },
   "out_of_range": {
    "default": "clamp",
    "description": "Inputs outside their declared min/max: clamp, or skip the sample.",
    "enum": [
     "clamp",
     "reject"
    ],
    "title": "Out Of Range",
    "type": "string"
   },
   "fmi_type": {
    "default": "auto",
    "description": "Which kind of FMU to run; auto: co-simulation if available.",
    "enum": [
     "auto",
     "CoSimulation",
     "ModelExchange"
    ],
    "title": "Fmi Type",
    "type": "string"
   },
   "solver": {
    "default": "CVode",
    "description": "Model exchange solver.",
    "enum": [
     "CVode",
     "Euler"
    ],
    "title": "Solver",
    "type": "string"
   },
   "solver_step_s": {
    "anyOf": [
     {
      "exclusiveMinimum": 0,
      "type": "number"
     },
     {
      "type": "null"
     }
    ],
    "default": null,
    "description": "Euler step; default: the FMU's default step or 1 ms.",
    "title": "Solver Step S"
   },
   "log_level": {
    "default": "errors",
    "description": "FMU log messages passed on to the processor log.",
    "enum": [
     "off",
     "errors",
     "all"
    ],
    "title": "Log Level",
    "type": "string"
   }
  },
  "required": [
   "fmu"
  ],
  "title": "FmuParams",
  "type": "object"
 },
 "source": "installed"
};

export const lowpassBlueprint: Blueprint = {
 "name": "lowpass",
 "title": "Low-pass filter (Butterworth)",
 "description": "Low-pass filter (Butterworth)\n\n    Passes frequencies below the cut-off and attenuates those above it; smooths noise.\n    Samples are treated as evenly spaced at `sample_rate_hz`; missing values are skipped\n    and the filter keeps its state over them.",
 "keeps_state": true,
 "params_schema": {
  "additionalProperties": false,
  "properties": {
   "signals": {
    "description": "The signals to filter.",
    "items": {
     "type": "string"
    },
    "minItems": 1,
    "title": "Signals",
    "type": "array"
   },
   "order": {
    "default": 4,
    "description": "Filter order: higher is a steeper roll-off (and more delay). A band filter has twice this many poles.",
    "maximum": 10,
    "minimum": 1,
    "title": "Order",
    "type": "integer"
   },
   "sample_rate_hz": {
    "description": "The sampling rate the filter is designed for, in Hz. Samples are treated as evenly spaced at this rate, whatever their timestamps say.",
    "exclusiveMinimum": 0,
    "title": "Sample Rate Hz",
    "type": "number"
   },
   "suffix": {
    "default": "",
    "description": "Appended to each signal name to name its output; empty: the output has the signal's own name.",
    "title": "Suffix",
    "type": "string"
   },
   "cutoff_hz": {
    "description": "Cut-off frequency in Hz (-3 dB); below half the sample rate.",
    "exclusiveMinimum": 0,
    "title": "Cutoff Hz",
    "type": "number"
   }
  },
  "required": [
   "signals",
   "sample_rate_hz",
   "cutoff_hz"
  ],
  "title": "CutoffParams",
  "type": "object"
 },
 "source": "installed"
};
