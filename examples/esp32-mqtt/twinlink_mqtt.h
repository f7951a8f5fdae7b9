// twinlink_mqtt: the topics and messages of twinlink's MQTT scheme (docs/mqtt.md and
// docs/protocol.md in the twinlink repository), in portable C++11 without Arduino headers or
// heap use, so the same code runs on the board and in the host tests (test/).
//
// Every function writes into a buffer the caller owns and returns false, leaving no partial
// message to send, when the buffer is too small or an input cannot be sent (NaN, infinity,
// text that is not UTF-8, a name that is not allowed in a topic).
//
// Topics:   {prefix}/{twin}/{device}/telemetry              device -> platform
//           {prefix}/{twin}/{device}/commands/{id}          platform -> device
//           {prefix}/{twin}/{device}/commands/{id}/delivered, .../result
//           {prefix}/{twin}/{device}/properties/reported    device -> platform
//           {prefix}/{twin}/{device}/properties/desired     platform -> device
//           {prefix}/{twin}/{device}/status, acks, errors
#ifndef TWINLINK_MQTT_H
#define TWINLINK_MQTT_H

#include <stddef.h>
#include <stdint.h>

#include "twinlink_json.h"

namespace twinlink {

// The last topic levels, for device_topic().
static const char kTelemetry[] = "telemetry";
static const char kCommandFilter[] = "commands/+";  // subscribe: every command of the device
static const char kReported[] = "properties/reported";
static const char kDesired[] = "properties/desired";
static const char kStatus[] = "status";  // "online", or "offline" as the will message
static const char kErrors[] = "errors";  // what the platform refused, and why
static const char kAcks[] = "acks";
// The last level of command_topic().
static const char kDelivered[] = "delivered";
static const char kResult[] = "result";

static const size_t kCommandIdSize = 65;    // ids are 1-64 characters of [A-Za-z0-9_-]
static const size_t kCommandNameSize = 64;  // longer command names are refused

// Where a device's topics are: the platform's prefix ("twinlink"), the twin's slug and the
// device's name, as given to `twinlink devices add SLUG NAME`.
struct Device {
  const char* prefix;
  const char* twin;
  const char* name;
};

// -- topics ---------------------------------------------------------------------------------

// The names the platform accepts (the same rules as src/twinlink/ingest/mqtt/topics.py).
bool valid_prefix(const char* prefix);        // no + or #, no / at either end
bool valid_twin(const char* twin);            // a slug: a-z 0-9 -, 1-64, no - at the ends
bool valid_device_name(const char* name);     // [A-Za-z0-9][A-Za-z0-9_.:-]{0,63}
bool valid_command_id(const char* id);        // [A-Za-z0-9_-]{1,64}
bool valid_stream(const char* stream);        // [a-z][a-z0-9_-]{0,63}

// "{prefix}/{twin}/{device}/{leaf}", leaf one of the constants above.
bool device_topic(char* out, size_t size, const Device& device, const char* leaf);
// "{prefix}/{twin}/{device}/telemetry", or ".../telemetry/{stream}" for a stream other than
// the twin's main one (stream nullptr or "": the main one, named "telemetry").
bool telemetry_topic(char* out, size_t size, const Device& device, const char* stream);
// "{prefix}/{twin}/{device}/commands/{id}/{leaf}" (leaf kDelivered or kResult).
bool command_topic(char* out, size_t size, const Device& device, const char* command_id,
                   const char* leaf);
// The id of a command topic of this device ("{base}/commands/{id}"), into out.
bool command_id_from_topic(const char* topic, const Device& device, char* out, size_t size);

// -- messages the device sends --------------------------------------------------------------

// One sample at the platform's clock: {"angle": 0.1, "force": 0.97}.
bool format_telemetry(char* out, size_t size, const Field* values, size_t count);

// Samples gathered into one message, each with its own time (ms since the Unix epoch):
// {"time_unit":"ms","samples":[{"time":1732200000123,"values":{...}}, ...]}.
// add() refuses a sample that does not fit and leaves the batch as it was, so the caller can
// publish what is there, clear() and add the sample again.
class TelemetryBatch {
 public:
  TelemetryBatch(char* buffer, size_t size);

  void clear();
  // time_ms 0: no time; the platform stamps it on arrival (only sensible one sample a batch).
  bool add(uint64_t time_ms, const Field* values, size_t count);
  size_t count() const { return count_; }
  // The batch as JSON, valid until the next add() or clear().
  const char* payload();
  size_t length() const { return writer_.length() + 2; }

 private:
  char* buffer_;
  JsonWriter writer_;
  size_t count_;
};

// commands/{id}/delivered: the platform reads nothing from it; "{}" reads better in logs.
bool format_delivered(char* out, size_t size);
// commands/{id}/result: {"status":"succeeded","result":{...}} (no "result" when count is 0).
bool format_result_succeeded(char* out, size_t size, const Field* result, size_t count);
// commands/{id}/result: {"status":"failed","error":"..."}.
bool format_result_failed(char* out, size_t size, const char* error);
// properties/reported: {"sample_rate": 50, "paused": false}.
bool format_reported(char* out, size_t size, const Field* properties, size_t count);

// -- messages the platform sends ------------------------------------------------------------

// A command: {"id": "...", "name": "set_sample_rate", "args": {"value": 50}, "expires": ...}.
struct Command {
  char id[kCommandIdSize];
  char name[kCommandNameSize];
  bool has_value;  // args.value was there and a number
  double value;
  const char* error;  // why parse_command() returned false
};

// Reads a command from its topic and payload (as PubSubClient hands them over: the payload
// is not NUL-terminated). False when the topic is not a command topic of this device (id
// empty) or the payload cannot be read (id set: answer the command as failed with error).
bool parse_command(const char* topic, const char* payload, size_t length, const Device& device,
                   Command* out);

// properties/desired: {"properties": {"sample_rate": 20}, "version": 4}. True, with *value
// set, when the payload is well-formed and holds `property` as a number.
bool parse_desired_number(const char* payload, size_t length, const char* property,
                          double* value);

}  // namespace twinlink

#endif  // TWINLINK_MQTT_H
