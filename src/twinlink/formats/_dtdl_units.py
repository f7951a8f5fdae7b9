"""DTDL v3's QuantitativeTypes extension (dtmi:dtdl:extension:quantitativeTypes;1): its
semantic types, their unit types and units, and the unit symbols twinlink documents use.

In DTDL v3 a unit is not part of the core language: an element is co-typed with a semantic
type (`"@type": ["Telemetry", "Temperature"]`) and names a unit of that type's unit type
(`"unit": "degreeCelsius"`), and the Interface's `@context` lists the extension. The table is
the extension's own (DTDL/v3/DTDL.quantitativeTypes.v1.md in Azure/opendigitaltwins-dtdl).
"""

from __future__ import annotations

QUANTITATIVE_CONTEXT = "dtmi:dtdl:extension:quantitativeTypes;1"

_POWER = (
    "britishThermalUnitPerHour gigajoulePerHour gigawatt horsepower joulePerHour "
    "joulePerSecond kiloBritishThermalUnitPerHour kilojoulePerHour kilojoulePerSecond "
    "kilowatt kilowattHourPerYear megajoulePerHour megawatt microwatt milliwatt "
    "tonOfRefrigeration watt"
)
_DATA = "bit byte exbibit exbibyte gibibit gibibyte kibibit kibibyte mebibit mebibyte tebibit "
_DATA += "tebibyte yobibit yobibyte zebibit zebibyte"

UNIT_TYPES: dict[str, frozenset[str]] = {
    name: frozenset(units.split())
    for name, units in {
        "AccelerationUnit": "centimetrePerSecondSquared gForce metrePerSecondSquared",
        "AngleUnit": "degreeOfArc minuteOfArc radian secondOfArc turn",
        "AngularAccelerationUnit": "radianPerSecondSquared",
        "AngularVelocityUnit": "degreePerSecond radianPerSecond revolutionPerMinute "
        "revolutionPerSecond",
        "ApparentEnergyUnit": "gigavoltAmpereHour kilovoltAmpereHour megavoltAmpereHour "
        "voltAmpereHour",
        "ApparentPowerUnit": "gigavoltAmpere kilovoltAmpere megavoltAmpere millivoltAmpere "
        "voltAmpere",
        "AreaUnit": "acre hectare squareCentimetre squareFoot squareInch squareKilometre "
        "squareMetre squareMillimetre",
        "CapacitanceUnit": "farad microfarad millifarad nanofarad picofarad",
        "Unitless": "partsPerBillion partsPerMillion partsPerQuadrillion partsPerTrillion "
        "percent unity",
        "CurrentUnit": "ampere kiloampere microampere milliampere",
        "DataRateUnit": " ".join(f"{u}PerSecond" for u in _DATA.split()),
        "DataSizeUnit": _DATA,
        "DensityUnit": "gramPerCubicMetre kilogramPerCubicMetre microgramPerCubicMetre "
        "milligramPerCubicMetre",
        "LengthUnit": "astronomicalUnit centimetre foot inch kilometre metre micrometre mile "
        "millimetre nanometre nauticalMile",
        "ChargeUnit": "ampereHour coulomb milliampereHour",
        "EnergyUnit": "britishThermalUnit electronvolt gigajoule gigawattHour joule "
        "kiloBritishThermalUnit kilojoule kilowattHour megaelectronvolt megajoule "
        "megawattHour milliwattHour terawattHour wattHour",
        "PowerUnit": _POWER,
        "ForceUnit": "newton ounce pound ton",
        "FrequencyUnit": "gigahertz hertz kilohertz megahertz millihertz",
        "IlluminanceUnit": "footcandle lux",
        "InductanceUnit": "henry microhenry millihenry",
        "IonizingRadiationDoseUnit": "gray microgray microsievert milligray millisievert sievert",
        "IrradianceUnit": "wattPerSquareMetre",
        "LuminanceUnit": "candelaPerSquareMetre",
        "LuminousFluxUnit": "lumen",
        "LuminousIntensityUnit": "candela",
        "MagneticFluxUnit": "maxwell weber",
        "MagneticInductionUnit": "gauss tesla",
        "MassUnit": "gram kilogram massPound microgram milligram slug tonne",
        "MassFlowRateUnit": "gramPerHour gramPerSecond kilogramPerHour kilogramPerSecond "
        "massPoundPerHour",
        "PressureUnit": "bar decapascal hectopascal inchesOfMercury inchesOfWater kilopascal "
        "millibar millimetresOfMercury pascal poundPerSquareInch",
        "RadioactivityUnit": "becquerel gigabecquerel kilobecquerel megabecquerel",
        "ReactiveEnergyUnit": "gigavoltAmpereReactiveHour kilovoltAmpereReactiveHour "
        "megavoltAmpereReactiveHour voltAmpereReactiveHour",
        "ReactivePowerUnit": "gigavoltAmpereReactive kilovoltAmpereReactive "
        "megavoltAmpereReactive millivoltAmpereReactive voltAmpereReactive",
        "ResistanceUnit": "kiloohm megaohm milliohm ohm",
        "SoundPressureUnit": "bel decibel",
        "TemperatureUnit": "degreeCelsius degreeFahrenheit kelvin",
        "TimeUnit": "day hour microsecond millisecond minute nanosecond second year",
        "TorqueUnit": "newtonMetre",
        "VelocityUnit": "centimetrePerSecond kilometrePerHour kilometrePerSecond knot "
        "metrePerHour metrePerSecond milePerHour milePerSecond",
        "VoltageUnit": "kilovolt megavolt microvolt millivolt volt",
        "VolumeUnit": "cubicCentimetre cubicFoot cubicInch cubicMetre fluidOunce gallon litre "
        "millilitre",
        "VolumeFlowRateUnit": "cubicFootPerMinute cubicMetrePerHour cubicMetrePerMinute "
        "cubicMetrePerSecond gallonPerHour gallonPerMinute litrePerHour litrePerMinute "
        "litrePerSecond millilitrePerHour millilitrePerMinute millilitrePerSecond",
    }.items()
}

# Semantic type -> its unit type. Not one to one: Humidity is expressed in DensityUnit,
# Luminosity in PowerUnit.
SEMANTIC_TYPES: dict[str, str] = {
    "Acceleration": "AccelerationUnit",
    "Angle": "AngleUnit",
    "AngularAcceleration": "AngularAccelerationUnit",
    "AngularVelocity": "AngularVelocityUnit",
    "ApparentEnergy": "ApparentEnergyUnit",
    "ApparentPower": "ApparentPowerUnit",
    "Area": "AreaUnit",
    "Capacitance": "CapacitanceUnit",
    "Concentration": "Unitless",
    "Current": "CurrentUnit",
    "DataRate": "DataRateUnit",
    "DataSize": "DataSizeUnit",
    "Density": "DensityUnit",
    "Distance": "LengthUnit",
    "ElectricCharge": "ChargeUnit",
    "Energy": "EnergyUnit",
    "EnergyRate": "PowerUnit",
    "Force": "ForceUnit",
    "Frequency": "FrequencyUnit",
    "Humidity": "DensityUnit",
    "Illuminance": "IlluminanceUnit",
    "Inductance": "InductanceUnit",
    "IonizingRadiationDose": "IonizingRadiationDoseUnit",
    "Irradiance": "IrradianceUnit",
    "Latitude": "AngleUnit",
    "Length": "LengthUnit",
    "Longitude": "AngleUnit",
    "Luminance": "LuminanceUnit",
    "Luminosity": "PowerUnit",
    "LuminousFlux": "LuminousFluxUnit",
    "LuminousIntensity": "LuminousIntensityUnit",
    "MagneticFlux": "MagneticFluxUnit",
    "MagneticInduction": "MagneticInductionUnit",
    "Mass": "MassUnit",
    "MassFlowRate": "MassFlowRateUnit",
    "Power": "PowerUnit",
    "Pressure": "PressureUnit",
    "Radioactivity": "RadioactivityUnit",
    "ReactiveEnergy": "ReactiveEnergyUnit",
    "ReactivePower": "ReactivePowerUnit",
    "RelativeDensity": "Unitless",
    "RelativeHumidity": "Unitless",
    "Resistance": "ResistanceUnit",
    "SoundPressure": "SoundPressureUnit",
    "Temperature": "TemperatureUnit",
    "Thrust": "ForceUnit",
    "TimeSpan": "TimeUnit",
    "Torque": "TorqueUnit",
    "Velocity": "VelocityUnit",
    "Voltage": "VoltageUnit",
    "Volume": "VolumeUnit",
    "VolumeFlowRate": "VolumeFlowRateUnit",
}

# twinlink's unit symbols (SI by convention, docs/dt-document.md "interface") -> the semantic
# type and the DTDL unit. The first symbol of each unit is the one import writes back; the
# others are accepted spellings of it. A symbol not listed here has no DTDL unit: the export
# keeps it in the element's twinlink note (docs/formats.md "DTDL").
SYMBOLS: dict[str, tuple[str, str]] = {
    "m/s^2": ("Acceleration", "metrePerSecondSquared"),
    "m/s2": ("Acceleration", "metrePerSecondSquared"),
    "rad": ("Angle", "radian"),
    "deg": ("Angle", "degreeOfArc"),
    "°": ("Angle", "degreeOfArc"),
    "rad/s": ("AngularVelocity", "radianPerSecond"),
    "rad/s^2": ("AngularAcceleration", "radianPerSecondSquared"),
    "rpm": ("AngularVelocity", "revolutionPerMinute"),
    "m^2": ("Area", "squareMetre"),
    "A": ("Current", "ampere"),
    "mA": ("Current", "milliampere"),
    "kg/m^3": ("Density", "kilogramPerCubicMetre"),
    "m": ("Length", "metre"),
    "mm": ("Length", "millimetre"),
    "cm": ("Length", "centimetre"),
    "km": ("Length", "kilometre"),
    "C": ("ElectricCharge", "coulomb"),
    "Ah": ("ElectricCharge", "ampereHour"),
    "J": ("Energy", "joule"),
    "kJ": ("Energy", "kilojoule"),
    "Wh": ("Energy", "wattHour"),
    "kWh": ("Energy", "kilowattHour"),
    "N": ("Force", "newton"),
    "Hz": ("Frequency", "hertz"),
    "kHz": ("Frequency", "kilohertz"),
    "lx": ("Illuminance", "lux"),
    "kg": ("Mass", "kilogram"),
    "g": ("Mass", "gram"),
    "t": ("Mass", "tonne"),
    "kg/s": ("MassFlowRate", "kilogramPerSecond"),
    "W": ("Power", "watt"),
    "kW": ("Power", "kilowatt"),
    "MW": ("Power", "megawatt"),
    "Pa": ("Pressure", "pascal"),
    "hPa": ("Pressure", "hectopascal"),
    "kPa": ("Pressure", "kilopascal"),
    "bar": ("Pressure", "bar"),
    "mbar": ("Pressure", "millibar"),
    "%": ("RelativeHumidity", "percent"),
    "ppm": ("Concentration", "partsPerMillion"),
    "ohm": ("Resistance", "ohm"),
    "Ω": ("Resistance", "ohm"),
    "dB": ("SoundPressure", "decibel"),
    "°C": ("Temperature", "degreeCelsius"),
    "degC": ("Temperature", "degreeCelsius"),
    "K": ("Temperature", "kelvin"),
    "°F": ("Temperature", "degreeFahrenheit"),
    "s": ("TimeSpan", "second"),
    "ms": ("TimeSpan", "millisecond"),
    "min": ("TimeSpan", "minute"),
    "h": ("TimeSpan", "hour"),
    "N m": ("Torque", "newtonMetre"),
    "Nm": ("Torque", "newtonMetre"),
    "m/s": ("Velocity", "metrePerSecond"),
    "km/h": ("Velocity", "kilometrePerHour"),
    "V": ("Voltage", "volt"),
    "mV": ("Voltage", "millivolt"),
    "kV": ("Voltage", "kilovolt"),
    "m^3": ("Volume", "cubicMetre"),
    "l": ("Volume", "litre"),
    "L": ("Volume", "litre"),
    "m^3/s": ("VolumeFlowRate", "cubicMetrePerSecond"),
    "m^3/h": ("VolumeFlowRate", "cubicMetrePerHour"),
    "l/min": ("VolumeFlowRate", "litrePerMinute"),
}

# DTDL unit -> the twinlink symbol import writes (the first listed above).
UNIT_SYMBOLS: dict[str, str] = {}
for _symbol, (_, _unit) in SYMBOLS.items():
    UNIT_SYMBOLS.setdefault(_unit, _symbol)
