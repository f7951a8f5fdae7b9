// esp32-mqtt: an ESP32 that streams a beam's angle and force to a twinlink twin over MQTT and
// obeys the twin's commands, like the Tingen rig of examples/tingen/ (README.md explains the
// wiring and setup).
//
// What it does, in order:
//   1. joins the WiFi network and sets its clock from NTP (for the samples' timestamps);
//   2. connects to the MQTT broker with its device token, leaving "offline" as its will;
//   3. subscribes to its commands and desired properties, and reports its properties;
//   4. samples the sensor SAMPLE_RATE_HZ times a second and publishes the samples in
//      batches every PUBLISH_INTERVAL_MS;
//   5. obeys pause, start and set_sample_rate, answering each command delivered + result;
//   6. when the connection drops, tries again after 1 s, 2 s, 4 s ... up to 30 s.
//
// Every message is built and read by twinlink_mqtt.h, which the host tests check against
// the platform's own parsers (`make test` in this folder).
#include <PubSubClient.h>
#include <WiFi.h>
#include <math.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>

#include "twinlink_mqtt.h"

#if __has_include("config.h")
#include "config.h"
#else
#error "Copy config.h.example to config.h and fill in your WiFi, broker and device token."
#endif

using twinlink::Field;
using twinlink::Value;

// -- settings that are not in config.h ------------------------------------------------------

static const double MIN_RATE_HZ = 1;    // what the Tingen twin's interface allows
static const double MAX_RATE_HZ = 100;
static const double NEWTONS_PER_RADIAN = 9.7;  // Tingen: force = angle * 2EI/L^2
static const uint32_t RETRY_MIN_MS = 1000;
static const uint32_t RETRY_MAX_MS = 30000;

// At 100 samples a second and 200 ms a message, 20 samples of about 90 bytes. PubSubClient
// keeps the topic and MQTT header in the same buffer, hence the extra 256 bytes below.
static const size_t BATCH_BYTES = 2048;
static const uint16_t MQTT_BUFFER_BYTES = BATCH_BYTES + 256;

// -- state ----------------------------------------------------------------------------------

static const twinlink::Device device = {MQTT_PREFIX, TWIN, DEVICE};

static WiFiClient network;
static PubSubClient mqtt(network);

static char batchBuffer[BATCH_BYTES];
static twinlink::TelemetryBatch batch(batchBuffer, sizeof batchBuffer);
static char telemetryTopic[128];  // the topics that stay the same, built in setup()
static char statusTopic[128];
static char desiredTopic[128];
static char errorsTopic[128];
static char topic[160];    // for one message at a time
static char payload[512];  // for one message at a time

static double sampleRateHz = SAMPLE_RATE_HZ;
static bool paused = false;
static uint32_t lastSampleUs = 0;
static uint32_t lastPublishMs = 0;
static uint32_t nextAttemptMs = 0;
static uint32_t retryDelayMs = RETRY_MIN_MS;

// -- time and the sensor --------------------------------------------------------------------

// True once NTP has set the clock (it starts at 1970). Before that, samples go without a
// time, one a message, and the platform stamps them when they arrive.
static bool clockIsSet() { return time(nullptr) > 1600000000; }

static uint64_t nowMs() {
  struct timeval now;
  gettimeofday(&now, nullptr);
  return static_cast<uint64_t>(now.tv_sec) * 1000 + static_cast<uint64_t>(now.tv_usec) / 1000;
}

// The beam's deflection in radians, always positive as on the Tingen rig.
static double readAngle() {
#if USE_SIMULATED_SENSOR
  // A tap every 10 s, then a damped swing at 2 Hz.
  double t = (millis() % 10000) / 1000.0;
  return 0.6 * exp(-t / 2.0) * fabs(cos(2.0 * M_PI * 2.0 * t));
#else
  // The ADC reads 0-3.3 V as 0-4095: a potentiometer between 3.3 V and GND, its wiper on
  // ANGLE_PIN, gives 0 to 1 rad.
  return analogRead(ANGLE_PIN) / 4095.0;
#endif
}

// -- sending --------------------------------------------------------------------------------

static bool publish(const char* to, const char* text, bool retained) {
  size_t length = strlen(text);
  bool sent = mqtt.publish(to, reinterpret_cast<const uint8_t*>(text), length, retained);
  if (!sent) Serial.printf("could not publish %u bytes to %s\n", (unsigned)length, to);
  return sent;
}

static void publishBatch() {
  const char* body = batch.payload();
  if (batch.count() > 0 && body != nullptr) publish(telemetryTopic, body, false);
  batch.clear();
  lastPublishMs = millis();
}

// properties/reported: the platform stores these and answers with what is still desired.
static void reportProperties() {
  const Field properties[] = {
      {"sample_rate", Value::of_number(sampleRateHz)},
      {"paused", Value::of_bool(paused)},
      {"device_id", Value::of_text(DEVICE)},
  };
  if (twinlink::device_topic(topic, sizeof topic, device, twinlink::kReported) &&
      twinlink::format_reported(payload, sizeof payload, properties, 3)) {
    publish(topic, payload, false);
  }
}

static void answerSucceeded(const char* id, const Field* result, size_t count) {
  if (twinlink::command_topic(topic, sizeof topic, device, id, twinlink::kResult) &&
      twinlink::format_result_succeeded(payload, sizeof payload, result, count)) {
    publish(topic, payload, false);
  }
}

static void answerFailed(const char* id, const char* error) {
  Serial.printf("command %s failed: %s\n", id, error);
  if (twinlink::command_topic(topic, sizeof topic, device, id, twinlink::kResult) &&
      twinlink::format_result_failed(payload, sizeof payload, error)) {
    publish(topic, payload, false);
  }
}

// -- sampling -------------------------------------------------------------------------------

static void takeSample() {
  double angle = readAngle();
  const Field values[] = {
      {"Cantilever_Angle_radians", Value::of_number(angle)},
      {"Input_F_in", Value::of_number(angle * NEWTONS_PER_RADIAN)},
  };
  uint64_t timeMs = clockIsSet() ? nowMs() : 0;
  if (!batch.add(timeMs, values, 2)) {  // full: send what is there and start a new batch
    publishBatch();
    if (!batch.add(timeMs, values, 2)) Serial.println("a sample does not fit in BATCH_BYTES");
  }
}

static void sampleAndPublish() {
  if (paused || !mqtt.connected()) return;
  uint32_t periodUs = static_cast<uint32_t>(1e6 / sampleRateHz);
  uint32_t nowUs = micros();
  if (nowUs - lastSampleUs >= periodUs) {
    // Keep to the rate on average; after a long stall (a reconnect) start the count again.
    lastSampleUs = nowUs - lastSampleUs > 10 * periodUs ? nowUs : lastSampleUs + periodUs;
    takeSample();
  }
  bool due = millis() - lastPublishMs >= PUBLISH_INTERVAL_MS;
  if (batch.count() > 0 && (due || !clockIsSet())) publishBatch();
}

static bool setSampleRate(double hz) {
  if (!(hz >= MIN_RATE_HZ && hz <= MAX_RATE_HZ)) return false;
  sampleRateHz = hz;
  return true;
}

// -- receiving ------------------------------------------------------------------------------

// A command. twinlink delivers a command at least once, so the same id may come twice; these
// commands can simply run again (a second pause leaves the rig paused).
static void obey(const char* commandTopic, const char* body, size_t length) {
  twinlink::Command command;
  bool read = twinlink::parse_command(commandTopic, body, length, device, &command);
  // Everything needed is now copied into `command`: publishing below reuses PubSubClient's
  // buffer, where commandTopic and body are.
  if (command.id[0] == '\0') {
    Serial.printf("ignored %s: %s\n", commandTopic, command.error);
    return;
  }
  if (twinlink::command_topic(topic, sizeof topic, device, command.id, twinlink::kDelivered) &&
      twinlink::format_delivered(payload, sizeof payload)) {
    publish(topic, payload, false);
  }
  if (!read) {
    answerFailed(command.id, command.error);
    return;
  }
  Serial.printf("command %s: %s\n", command.id, command.name);
  if (strcmp(command.name, "pause") == 0) {
    publishBatch();  // what was measured before the pause still goes
    paused = true;
    const Field result[] = {{"paused", Value::of_bool(true)}};
    answerSucceeded(command.id, result, 1);
  } else if (strcmp(command.name, "start") == 0) {
    paused = false;
    lastSampleUs = micros();
    const Field result[] = {{"paused", Value::of_bool(false)}};
    answerSucceeded(command.id, result, 1);
  } else if (strcmp(command.name, "set_sample_rate") == 0) {
    if (!command.has_value || !setSampleRate(command.value)) {
      answerFailed(command.id, "set_sample_rate needs args.value: a number from 1 to 100 (Hz)");
      return;
    }
    const Field result[] = {{"sample_rate", Value::of_number(sampleRateHz)}};
    answerSucceeded(command.id, result, 1);
  } else {
    answerFailed(command.id, "unknown command (this board knows pause, start and set_sample_rate)");
    return;
  }
  reportProperties();  // the twin shows the new state at once
}

// properties/desired: what people want set, e.g. `twinlink properties set tingen esp32
// sample_rate=20`. It comes right after subscribing, and whenever it changes.
static void applyDesired(const char* body, size_t length) {
  double hz;
  if (twinlink::parse_desired_number(body, length, "sample_rate", &hz) && setSampleRate(hz)) {
    Serial.printf("desired sample_rate %.1f Hz applied\n", hz);
    reportProperties();  // the platform then stops sending it as a difference
  }
}

// PubSubClient calls this from mqtt.loop() for each message on a subscribed topic. The
// payload is not NUL-terminated: use length.
static void onMessage(char* messageTopic, uint8_t* body, unsigned int length) {
  const char* text = reinterpret_cast<const char*>(body);
  if (strcmp(messageTopic, desiredTopic) == 0) {
    applyDesired(text, length);
  } else if (strcmp(messageTopic, errorsTopic) == 0) {
    // The platform refused something this board sent (a rejected sample, a bad topic).
    Serial.print("platform error: ");
    Serial.write(body, length);
    Serial.println();
  } else {
    obey(messageTopic, text, length);
  }
}

// -- connecting -----------------------------------------------------------------------------

static const char* mqttStateText(int state) {
  switch (state) {
    case MQTT_CONNECTION_TIMEOUT:
      return "no answer (is MQTT_HOST right, and the listener on 0.0.0.0?)";
    case MQTT_CONNECT_FAILED: return "cannot reach MQTT_HOST:MQTT_PORT";
    case MQTT_CONNECT_BAD_CREDENTIALS: return "the token was refused (check DEVICE_TOKEN)";
    case MQTT_CONNECT_UNAUTHORIZED: return "not authorized (check DEVICE_TOKEN)";
    case MQTT_CONNECT_BAD_CLIENT_ID: return "client id refused";
    case MQTT_CONNECT_UNAVAILABLE: return "the broker is unavailable";
    default: return "see PubSubClient's state()";
  }
}

static bool connectMqtt() {
  Serial.printf("connecting to MQTT %s:%u as %s/%s\n", MQTT_HOST, MQTT_PORT, TWIN, DEVICE);
  // The will: if the board vanishes, the broker publishes "offline" for it (external mode
  // ends the device's session on it). The client id is the device's name.
  if (!mqtt.connect(DEVICE, MQTT_USERNAME, MQTT_PASSWORD, statusTopic, 1, true, "offline")) {
    Serial.printf("MQTT connect failed (%d): %s\n", mqtt.state(), mqttStateText(mqtt.state()));
    return false;
  }
  publish(statusTopic, "online", true);
  // Commands and desired properties at QoS 1: they are not lost on a bad link. Errors are
  // only printed to the serial monitor.
  if (twinlink::device_topic(topic, sizeof topic, device, twinlink::kCommandFilter)) {
    mqtt.subscribe(topic, 1);
  }
  mqtt.subscribe(desiredTopic, 1);
  mqtt.subscribe(errorsTopic, 0);
  reportProperties();
  batch.clear();
  lastSampleUs = micros();
  lastPublishMs = millis();
  Serial.println("MQTT connected");
  return true;
}

// Called every loop: reconnects when needed, waiting longer after each failure (with some
// randomness, so a room of boards does not retry in step).
static void keepConnected() {
  if (mqtt.connected() || WiFi.status() != WL_CONNECTED) return;
  if (static_cast<int32_t>(millis() - nextAttemptMs) < 0) return;
  if (connectMqtt()) {
    retryDelayMs = RETRY_MIN_MS;
    return;
  }
  nextAttemptMs = millis() + retryDelayMs + random(0, retryDelayMs / 4 + 1);
  retryDelayMs = retryDelayMs * 2 > RETRY_MAX_MS ? RETRY_MAX_MS : retryDelayMs * 2;
}

// -- Arduino entry points -------------------------------------------------------------------

void setup() {
  Serial.begin(115200);
  Serial.println();
  // Build the fixed topics once; a twin or device name the platform would refuse stops here.
  if (!twinlink::telemetry_topic(telemetryTopic, sizeof telemetryTopic, device, STREAM) ||
      !twinlink::device_topic(statusTopic, sizeof statusTopic, device, twinlink::kStatus) ||
      !twinlink::device_topic(desiredTopic, sizeof desiredTopic, device, twinlink::kDesired) ||
      !twinlink::device_topic(errorsTopic, sizeof errorsTopic, device, twinlink::kErrors)) {
    Serial.println("TWIN, DEVICE, STREAM or MQTT_PREFIX in config.h is not a valid name");
    for (;;) delay(1000);
  }
  setSampleRate(SAMPLE_RATE_HZ);

  // 1. WiFi. The ESP32 reconnects to the network by itself after this.
  WiFi.mode(WIFI_STA);
  WiFi.begin(WIFI_SSID, WIFI_PASSWORD);
  Serial.printf("joining WiFi %s", WIFI_SSID);
  for (int i = 0; i < 40 && WiFi.status() != WL_CONNECTED; ++i) {
    delay(500);
    Serial.print(".");
  }
  Serial.println(WiFi.status() == WL_CONNECTED ? " joined" : " not yet (retrying)");

  // 2. The clock, in UTC; it is set in the background once the network is up.
  configTime(0, 0, NTP_SERVER);

  // 3. MQTT. The buffer holds a whole message with its topic; the default (256 bytes) is too
  // small for a batch of samples, and PubSubClient drops larger messages without a word.
  mqtt.setServer(MQTT_HOST, MQTT_PORT);
  mqtt.setCallback(onMessage);
  mqtt.setKeepAlive(15);
  mqtt.setSocketTimeout(5);  // a broker that does not answer blocks loop() at most 5 s
  if (!mqtt.setBufferSize(MQTT_BUFFER_BYTES)) Serial.println("no memory for the MQTT buffer");
  randomSeed(micros());
}

void loop() {
  keepConnected();
  mqtt.loop();  // reads incoming messages (onMessage) and keeps the connection alive
  sampleAndPublish();
}
