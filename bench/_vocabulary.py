"""The words and tables benchmark twins are made of.

Word lists by theme (joined into VOCABULARY, from which keywords and description words are
drawn), the kinds of equipment with their own keywords, sites, manufacturers, and the feature
templates of public and group parts. `_twins.py` draws from these; changing them changes the
generated documents, and so the benchmark's data.
"""

from __future__ import annotations


def _words(text: str) -> list[str]:
    return text.split()


QUANTITIES = _words("""
temperature pressure vibration acceleration velocity speed position distance displacement load
weight force torque strain stress humidity flow level current voltage power energy frequency
rpm noise acoustic emission radiation irradiance wind rainfall corrosion wear friction
lubrication viscosity density thickness tension deflection angle tilt orientation consumption
efficiency throughput cycle uptime downtime runtime hours fatigue crack
""")

THINGS = _words("""
bearing gearbox motor pump valve compressor fan blade rotor stator shaft spindle belt chain
hook rope sheave trolley bridge hoist brake clutch coupling inverter transformer battery cable
sensor accelerometer thermocouple camera lidar encoder actuator cylinder hydraulic pneumatic
nozzle filter boiler chiller burner furnace conveyor gripper robot tool fixture mould die weld
seam frame beam column foundation tank pipe duct damper heat exchanger
""")

DATA = _words("""
data history historical time-series realtime real-time live stream dashboard trend report alarm
alert event log logbook record archive backup export csv json api rest graphql mqtt opc ua
modbus profinet ethernet wifi lora 5g cloud edge gateway database historian analytics analysis
statistics model simulation fmu fem cad plm bim geometry drawing design drawings 3d point-cloud
scan image video thermal infrared spectrum fft anomaly prediction forecast estimate
optimisation control setpoint command monitoring diagnostics prognostics
""")

WORK = _words("""
maintenance inspection repair service calibration commissioning installation spare parts
warranty manual documentation procedure checklist training safety certificate audit permit
booking reservation schedule calendar shift operator owner contact support ticket work order
supplier purchase cost budget invoice quality tolerance defect scrap yield production batch
recipe order planning capacity utilisation sustainability emissions carbon
""")

PLACES = _words("""
hall laboratory workshop factory plant line cell station site campus warehouse yard dock
harbour substation rooftop basement tunnel outdoor indoor greenhouse cleanroom office
""")

VOCABULARY: list[str] = list(dict.fromkeys(QUANTITIES + THINGS + DATA + WORK + PLACES))

EQUIPMENT = [
    ("overhead crane", ["hoist", "trolley", "bridge", "hook", "rope", "load"]),
    ("hydraulic press", ["hydraulic", "pressure", "force", "cylinder", "die"]),
    ("CNC milling machine", ["spindle", "tool", "rpm", "vibration", "fixture"]),
    ("wind turbine", ["blade", "rotor", "wind", "gearbox", "power"]),
    ("heat pump", ["temperature", "compressor", "energy", "efficiency"]),
    ("air handling unit", ["fan", "filter", "humidity", "damper", "duct"]),
    ("conveyor line", ["belt", "conveyor", "speed", "throughput"]),
    ("industrial robot", ["robot", "gripper", "position", "torque", "cycle"]),
    ("centrifugal pump", ["pump", "flow", "pressure", "bearing", "vibration"]),
    ("screw compressor", ["compressor", "pressure", "temperature", "energy"]),
    ("power transformer", ["transformer", "voltage", "current", "temperature"]),
    ("battery storage", ["battery", "energy", "voltage", "temperature"]),
    ("solar inverter", ["inverter", "power", "irradiance", "voltage"]),
    ("steam boiler", ["boiler", "burner", "pressure", "temperature"]),
    ("chiller", ["chiller", "temperature", "compressor", "energy"]),
    ("electric forklift", ["battery", "load", "position", "hours"]),
    ("3D printer", ["3d", "temperature", "nozzle", "model"]),
    ("injection moulding machine", ["mould", "pressure", "temperature", "cycle"]),
    ("lathe", ["spindle", "tool", "rpm", "wear"]),
    ("cantilever test rig", ["beam", "deflection", "strain", "angle", "fem"]),
    ("gearbox test bench", ["gearbox", "torque", "vibration", "lubrication"]),
    ("electric motor", ["motor", "current", "rpm", "temperature", "bearing"]),
    ("diesel generator", ["power", "fuel", "hours", "vibration"]),
    ("weather station", ["wind", "rainfall", "temperature", "humidity"]),
    ("paper machine", ["rope", "speed", "thickness", "tension", "quality"]),
    ("welding cell", ["weld", "seam", "robot", "current", "quality"]),
    ("packaging line", ["conveyor", "throughput", "batch", "defect"]),
    ("laser cutter", ["thickness", "power", "tool", "quality"]),
    ("passenger elevator", ["motor", "rope", "brake", "position", "safety"]),
    ("footbridge", ["bridge", "strain", "deflection", "fatigue", "crack"]),
    ("water tower", ["tank", "level", "pressure", "flow"]),
    ("district heating substation", ["heat exchanger", "temperature", "flow", "energy"]),
    ("ship engine", ["engine", "fuel", "rpm", "temperature", "emissions"]),
    ("tram", ["motor", "brake", "position", "speed", "energy"]),
    ("sawmill line", ["blade", "throughput", "wear", "yield"]),
]

SITES = [
    ("Otaniemi", "Espoo"),
    ("Hervanta", "Tampere"),
    ("Linnanmaa", "Oulu"),
    ("Gløshaugen", "Trondheim"),
    ("Kupittaa", "Turku"),
    ("Skinnarila", "Lappeenranta"),
    ("Palosaari", "Vaasa"),
    ("Lindholmen", "Gothenburg"),
    ("Brainport", "Eindhoven"),
    ("TU Campus", "Delft"),
    ("Melaten", "Aachen"),
    ("Garching", "Munich"),
    ("Katrinebjerg", "Aarhus"),
    ("Ideon", "Lund"),
    ("Marineholmen", "Bergen"),
    ("Ullandhaug", "Stavanger"),
    ("Valla", "Linköping"),
    ("Ångström", "Uppsala"),
    ("Cortex", "Odense"),
    ("Kuopio harbour", "Kuopio"),
]

SITE_KINDS = [
    "industrial hall",
    "test laboratory",
    "production plant",
    "assembly line",
    "energy centre",
    "workshop",
]

MANUFACTURERS = [
    "Konecranes",
    "ABB",
    "Siemens",
    "KUKA",
    "Wärtsilä",
    "Valmet",
    "Danfoss",
    "Grundfos",
    "Bosch Rexroth",
    "Schneider Electric",
    "Fanuc",
    "Vestas",
    "Kone",
    "Atlas Copco",
    "Metso",
    "Sandvik",
    "Festo",
    "Beckhoff",
    "Omron",
    "Yaskawa",
    "Trumpf",
    "DMG Mori",
    "Hiab",
    "Ponsse",
]

FEATURES = [
    (
        "Historian",
        "Long-term store for the {eq}'s operational time series ({a}, {b} and {c}), "
        "sampled every {n} seconds. Offers dashboards in the browser and a REST API for bulk "
        "queries.",
        ["historical", "history", "time-series", "data"],
    ),
    (
        "OPC UA server",
        "OPC UA server wired to the PLC of the {eq}. Exposes {a} and {b} for "
        "real-time reading, and the {c} set-point for writing.",
        ["opc", "ua", "real-time", "control"],
    ),
    (
        "Condition monitoring",
        "Vendor service that tracks the condition of the {eq}: {a}, {b} and "
        "wear of the {c}, with alerts when a limit is crossed.",
        ["condition", "monitoring", "alerts"],
    ),
    (
        "CAD store",
        "Design data of the {eq} in the PLM system, including a 3D model of the {a} "
        "and drawings of the {b}.",
        ["cad", "3d", "plm", "model", "drawings"],
    ),
    (
        "Maintenance log",
        "Work orders, inspections and repairs of the {eq} since {year}; each "
        "entry names the {a} or {b} that was serviced.",
        ["maintenance", "repair", "inspection"],
    ),
    (
        "Energy meter",
        "Sub-meter for the {eq} measuring {a}, {b} and energy use every {n} seconds.",
        ["energy", "power", "consumption"],
    ),
    (
        "Vibration analysis",
        "Accelerometers on the {a} and {b}; FFT spectra and RMS trends every "
        "{n} minutes, used to spot {c} faults early.",
        ["vibration", "fft", "accelerometer", "bearing"],
    ),
    (
        "Live dashboard",
        "Browser dashboard with live {a}, {b} and {c} of the {eq}.",
        ["dashboard", "live", "real-time"],
    ),
    (
        "Simulation model",
        "FMU of the {eq} built from the {a} and {b} equations; runs faster than "
        "real time and can be fed with live data.",
        ["simulation", "fmu", "model"],
    ),
    (
        "Sensor manager",
        "Settings of the sensors retrofitted to the {eq} ({a}, {b}); viewed and "
        "changed in the browser or through a REST API.",
        ["sensor", "sensors", "management", "retrofit"],
    ),
    (
        "Alarm history",
        "Every alarm and event the {eq}'s controller raised, with the {a} and {b} "
        "values at that moment.",
        ["alarm", "event", "log"],
    ),
    (
        "Spare parts catalogue",
        "Part numbers, suppliers and stock of spare {a} and {b} for the {eq}.",
        ["spare", "parts", "supplier"],
    ),
    (
        "Operator manual",
        "Manufacturer's manual and safety instructions for the {eq}, as PDF.",
        ["manual", "documentation", "safety"],
    ),
    (
        "Camera stream",
        "Video stream of the {eq} from a camera facing the {a}.",
        ["camera", "video", "stream"],
    ),
    (
        "Thermal imaging",
        "Infrared images of the {a} and {b} taken on each inspection round.",
        ["thermal", "infrared", "image", "inspection"],
    ),
    (
        "MQTT broker",
        "Telemetry topics of the {eq}: {a}, {b} and {c}, published every {n} seconds.",
        ["mqtt", "stream", "telemetry"],
    ),
    (
        "Calibration records",
        "Calibration certificates of the {a} and {b} sensors of the {eq}.",
        ["calibration", "certificate", "quality"],
    ),
    (
        "Anomaly detection",
        "Machine-learning service that scores {a} and {b} of the {eq} and flags unusual behaviour.",
        ["anomaly", "analytics", "prediction"],
    ),
    (
        "Remaining useful life",
        "Estimate of the remaining life of the {a}, from {b} and {c} history.",
        ["prognostics", "estimate", "fatigue"],
    ),
    (
        "Booking calendar",
        "Shared calendar for reserving the {eq} for experiments; also lists "
        "planned maintenance breaks.",
        ["booking", "reservation", "calendar", "schedule"],
    ),
    (
        "Finite element model",
        "FEM model of the {a} and {b} of the {eq}, with the load cases used in design.",
        ["fem", "model", "stress", "strain"],
    ),
    (
        "Production scheduler",
        "Planned orders and batches on the {eq}, with the expected {a}.",
        ["production", "planning", "schedule", "order"],
    ),
    (
        "Quality inspection",
        "Measured {a} and {b} of each batch, with defects and scrap.",
        ["quality", "inspection", "defect", "tolerance"],
    ),
    (
        "Remote control API",
        "Commands to start, stop and set the {a} of the {eq}.",
        ["control", "command", "api", "setpoint"],
    ),
]

GROUP_FEATURES = [
    (
        "Lab wiki",
        "Notes of the lab team on running experiments with the {eq}: {a}, {b} limits "
        "and who to ask.",
        ["documentation", "procedure", "training"],
    ),
    (
        "Network access",
        "How to reach the {eq}'s local network; the VPN profile is given on request.",
        ["network", "vpn", "access"],
    ),
    (
        "Shift log",
        "Operator shift notes on the {eq}, including {a} problems.",
        ["shift", "operator", "logbook"],
    ),
]

# Owners of machines; the generator adds "<manufacturer> service" to these.
OWNERS = [
    "Aalto University",
    "NTNU",
    "VTT",
    "TU Delft",
    "RWTH Aachen",
    "DTU",
    "Chalmers",
]

# How to get access to a feature.
REQUIREMENTS = [
    "A user account is needed.",
    "Open to everyone on the campus network.",
    "Ask the twin's contact for an API key.",
    "VPN access to the lab network is needed.",
]

RETENTIONS = ["1 year", "5 years", "10 years", "forever"]

# Queries of the last kind in the mix: places and makers, and a few with no hits (misspellings).
FIXED_QUERIES = [
    "otaniemi crane",
    "trondheim",
    "konecranes hoist",
    "espoo pump",
    "zzyzx",
    "bearing vibraton",
]
