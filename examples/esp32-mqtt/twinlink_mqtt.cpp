// twinlink_mqtt: see twinlink_mqtt.h. Portable C++11, as twinlink_json.cpp.
#include "twinlink_mqtt.h"

#include <stdio.h>
#include <string.h>

namespace twinlink {

namespace {

bool is_lower_or_digit(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); }
bool is_alnum(char c) { return is_lower_or_digit(c) || (c >= 'A' && c <= 'Z'); }
// The text after `part` at the start of s, or nullptr when s does not start with it.
const char* after(const char* s, const char* part) {
  size_t n = strlen(part);
  return strncmp(s, part, n) == 0 ? s + n : nullptr;
}

}  // namespace

// -- topics ---------------------------------------------------------------------------------

bool valid_prefix(const char* prefix) {
  if (prefix == nullptr || prefix[0] == '\0' || prefix[0] == '/') return false;
  if (strpbrk(prefix, "+#") != nullptr) return false;
  return prefix[strlen(prefix) - 1] != '/';
}

bool valid_twin(const char* twin) {
  if (twin == nullptr) return false;
  size_t n = strlen(twin);
  if (n == 0 || n > 64 || twin[0] == '-' || twin[n - 1] == '-') return false;
  for (size_t i = 0; i < n; ++i) {
    if (!is_lower_or_digit(twin[i]) && twin[i] != '-') return false;
  }
  return true;
}

bool valid_device_name(const char* name) {
  if (name == nullptr || !is_alnum(name[0])) return false;
  size_t n = strlen(name);
  if (n > 64) return false;
  for (size_t i = 1; i < n; ++i) {
    if (!is_alnum(name[i]) && strchr("_.:-", name[i]) == nullptr) return false;
  }
  return true;
}

bool valid_command_id(const char* id) {
  if (id == nullptr) return false;
  size_t n = strlen(id);
  if (n == 0 || n > 64) return false;
  for (size_t i = 0; i < n; ++i) {
    if (!is_alnum(id[i]) && id[i] != '_' && id[i] != '-') return false;
  }
  return true;
}

bool valid_stream(const char* stream) {
  if (stream == nullptr || !(stream[0] >= 'a' && stream[0] <= 'z')) return false;
  size_t n = strlen(stream);
  if (n > 64) return false;
  for (size_t i = 1; i < n; ++i) {
    if (!is_lower_or_digit(stream[i]) && stream[i] != '_' && stream[i] != '-') return false;
  }
  return true;
}

namespace {

bool valid_device(const Device& device) {
  return valid_prefix(device.prefix) && valid_twin(device.twin) &&
         valid_device_name(device.name);
}

bool fits(int written, size_t size) { return written >= 0 && static_cast<size_t>(written) < size; }

bool finish(const JsonWriter& writer, char* out, size_t size) {
  if (writer.ok()) return true;
  if (out != nullptr && size > 0) out[0] = '\0';  // never half a message
  return false;
}

bool format_object(char* out, size_t size, const Field* fields, size_t count) {
  JsonWriter writer(out, size);
  writer.open_object().fields(fields, count).close_object();
  return finish(writer, out, size);
}

}  // namespace

bool device_topic(char* out, size_t size, const Device& device, const char* leaf) {
  if (out == nullptr || size == 0) return false;
  out[0] = '\0';
  if (leaf == nullptr || !valid_device(device)) return false;
  int n = snprintf(out, size, "%s/%s/%s/%s", device.prefix, device.twin, device.name, leaf);
  if (fits(n, size)) return true;
  out[0] = '\0';
  return false;
}

bool telemetry_topic(char* out, size_t size, const Device& device, const char* stream) {
  if (stream == nullptr || stream[0] == '\0') return device_topic(out, size, device, kTelemetry);
  if (out == nullptr || size == 0) return false;
  out[0] = '\0';
  if (!valid_device(device) || !valid_stream(stream)) return false;
  int n = snprintf(out, size, "%s/%s/%s/%s/%s", device.prefix, device.twin, device.name,
                   kTelemetry, stream);
  if (fits(n, size)) return true;
  out[0] = '\0';
  return false;
}

bool command_topic(char* out, size_t size, const Device& device, const char* command_id,
                   const char* leaf) {
  if (out == nullptr || size == 0) return false;
  out[0] = '\0';
  if (leaf == nullptr || !valid_device(device) || !valid_command_id(command_id)) return false;
  int n = snprintf(out, size, "%s/%s/%s/commands/%s/%s", device.prefix, device.twin,
                   device.name, command_id, leaf);
  if (fits(n, size)) return true;
  out[0] = '\0';
  return false;
}

bool command_id_from_topic(const char* topic, const Device& device, char* out, size_t size) {
  if (out == nullptr || size == 0) return false;
  out[0] = '\0';
  if (topic == nullptr || !valid_device(device)) return false;
  const char* rest = after(topic, device.prefix);
  rest = rest ? after(rest, "/") : nullptr;
  rest = rest ? after(rest, device.twin) : nullptr;
  rest = rest ? after(rest, "/") : nullptr;
  rest = rest ? after(rest, device.name) : nullptr;
  rest = rest ? after(rest, "/commands/") : nullptr;
  if (rest == nullptr || !valid_command_id(rest) || strlen(rest) >= size) return false;
  memcpy(out, rest, strlen(rest) + 1);
  return true;
}

// -- messages the device sends --------------------------------------------------------------

bool format_telemetry(char* out, size_t size, const Field* values, size_t count) {
  if (count > 0) return format_object(out, size, values, count);
  if (out != nullptr && size > 0) out[0] = '\0';  // {} is no sample: the platform refuses it
  return false;
}

// The writer gets all but the last two bytes: payload() closes the batch with "]}" there.
TelemetryBatch::TelemetryBatch(char* buffer, size_t size)
    : buffer_(buffer), writer_(buffer, size > 2 ? size - 2 : 0), count_(0) {
  clear();
}

void TelemetryBatch::clear() {
  writer_.rewind(0);
  count_ = 0;
  writer_.open_object().key("time_unit").text("ms").key("samples").open_array();
}

bool TelemetryBatch::add(uint64_t time_ms, const Field* values, size_t count) {
  if (!writer_.ok() || values == nullptr || count == 0) return false;
  size_t mark = writer_.length();
  writer_.open_object();
  if (time_ms != 0) writer_.key("time").integer(time_ms);
  writer_.key("values").open_object().fields(values, count).close_object().close_object();
  if (!writer_.ok()) {
    writer_.rewind(mark);
    return false;
  }
  ++count_;
  return true;
}

const char* TelemetryBatch::payload() {
  if (!writer_.ok()) return nullptr;  // the buffer cannot even hold an empty batch
  size_t n = writer_.length();
  buffer_[n] = ']';
  buffer_[n + 1] = '}';
  buffer_[n + 2] = '\0';
  return buffer_;
}

bool format_delivered(char* out, size_t size) { return format_object(out, size, nullptr, 0); }

bool format_result_succeeded(char* out, size_t size, const Field* result, size_t count) {
  JsonWriter writer(out, size);
  writer.open_object().key("status").text("succeeded");
  if (count > 0) writer.key("result").open_object().fields(result, count).close_object();
  writer.close_object();
  return finish(writer, out, size);
}

bool format_result_failed(char* out, size_t size, const char* error) {
  JsonWriter writer(out, size);
  writer.open_object().key("status").text("failed").key("error").text(error).close_object();
  return finish(writer, out, size);
}

bool format_reported(char* out, size_t size, const Field* properties, size_t count) {
  return format_object(out, size, properties, count);
}

// -- messages the platform sends ------------------------------------------------------------

namespace {

const char kNoPayload[] = "the command has no payload";

bool read_args(JsonReader& json, Command* command) {
  return json.object([&](const char* key) -> bool {
    if (strcmp(key, "value") != 0) return json.skip();
    command->has_value = json.next_is_number();  // the last "value" counts, as in Python
    return command->has_value ? json.number(&command->value) : json.skip();
  });
}

bool read_command(JsonReader& json, Command* command) {
  bool read = json.object([&](const char* key) -> bool {
    if (strcmp(key, "name") == 0) {
      bool complete = false;
      return json.string(command->name, sizeof command->name, &complete) &&
             (complete || json.fail("the command name is too long"));
    }
    if (strcmp(key, "id") == 0) {  // the topic names the command; the payload must agree
      char id[kCommandIdSize];
      bool complete = false;
      return json.string(id, sizeof id, &complete) &&
             ((complete && strcmp(id, command->id) == 0) ||
              json.fail("the payload's id is not the topic's"));
    }
    if (strcmp(key, "args") != 0) return json.skip();
    command->has_value = false;  // a second "args" replaces the first, as in Python
    command->value = 0.0;
    return json.next_is_object() ? read_args(json, command) : json.skip();
  });
  if (!read) return false;
  if (!json.at_end()) return json.fail("text after the JSON");
  return command->name[0] != '\0' || json.fail("the command has no name");
}

}  // namespace

bool parse_command(const char* topic, const char* payload, size_t length, const Device& device,
                   Command* out) {
  if (out == nullptr) return false;
  memset(out, 0, sizeof *out);
  if (!command_id_from_topic(topic, device, out->id, sizeof out->id)) {
    out->error = "not a command topic of this device";
    return false;
  }
  if (payload == nullptr || length == 0) {
    out->error = kNoPayload;
    return false;
  }
  JsonReader json(payload, length);
  if (read_command(json, out)) return true;
  out->name[0] = '\0';
  out->has_value = false;
  out->value = 0.0;
  out->error = json.error();
  return false;
}

bool parse_desired_number(const char* payload, size_t length, const char* property,
                          double* value) {
  if (payload == nullptr || property == nullptr || value == nullptr) return false;
  JsonReader json(payload, length);
  bool found = false;
  double number = 0.0;
  bool read = json.object([&](const char* key) -> bool {
    if (strcmp(key, "properties") != 0 || !json.next_is_object()) return json.skip();
    return json.object([&](const char* name) -> bool {
      if (strcmp(name, property) != 0 || !json.next_is_number()) return json.skip();
      found = true;
      return json.number(&number);
    });
  });
  if (!read || !json.at_end() || !found) return false;
  *value = number;
  return true;
}

}  // namespace twinlink
