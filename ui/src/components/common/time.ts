// Times as the user reads them: the browser's language and time zone (Intl), for tables, the
// charts' time axis and their legend. Spaces become no-break spaces so that a time never wraps
// over two lines of a table cell.

type Style = "dateTime" | "clock" | "clockMs" | "minutes" | "day" | "month" | "instant";

const OPTIONS: Record<Style, Intl.DateTimeFormatOptions> = {
  dateTime: { dateStyle: "short", timeStyle: "medium" },
  clock: { hour: "2-digit", minute: "2-digit", second: "2-digit" },
  clockMs: { hour: "2-digit", minute: "2-digit", second: "2-digit", fractionalSecondDigits: 3 },
  minutes: { hour: "2-digit", minute: "2-digit" },
  day: { month: "short", day: "numeric" },
  month: { month: "short", year: "numeric" },
  instant: { year: "numeric", month: "short", day: "numeric", hour: "2-digit", minute: "2-digit", second: "2-digit", fractionalSecondDigits: 3 },
};

// Making a formatter costs far more than using one, and the live chart formats its axis at
// every frame.
const formatters = new Map<string, Intl.DateTimeFormat>();

function formatter(style: Style, locale: string | undefined): Intl.DateTimeFormat {
  const key = `${locale ?? ""}|${style}`;
  let found = formatters.get(key);
  if (!found) {
    found = new Intl.DateTimeFormat(locale, OPTIONS[style]);
    formatters.set(key, found);
  }
  return found;
}

function noWrap(text: string): string {
  return text.replace(/\s/g, "\u00a0");
}

function format(style: Style, date: Date, locale?: string): string {
  return noWrap(formatter(style, locale).format(date));
}

/** A date and time (an ISO string from the API) in the user's locale; "never" when absent. */
export function formatTime(iso: string | null | undefined, locale?: string): string {
  if (!iso) return "never";
  const date = new Date(iso);
  return Number.isNaN(date.getTime()) ? iso : format("dateTime", date, locale);
}

/** A time given in ms since the epoch, as formatTime does. */
export function formatEpochMs(ms: number, locale?: string): string {
  return format("dateTime", new Date(ms), locale);
}

/** The time of day only (for lists of recent events). */
export function formatClock(ms: number, locale?: string): string {
  return format("clock", new Date(ms), locale);
}

/** A chart's cursor time (seconds since the epoch), to the millisecond. */
export function formatInstant(seconds: number, locale?: string): string {
  return format("instant", new Date(seconds * 1000), locale);
}

/** Labels of the time axis' ticks (seconds since the epoch) `incr` seconds apart: as fine as
 * the spacing needs, and with the day under the first tick and wherever the day changes. */
export function timeAxisValues(splits: number[], incr: number, locale?: string): string[] {
  if (incr >= 28 * 86400) return splits.map((s) => format("month", new Date(s * 1000), locale));
  if (incr >= 86400) return splits.map((s) => format("day", new Date(s * 1000), locale));
  const style: Style = incr < 1 ? "clockMs" : incr < 60 ? "clock" : "minutes";
  let day = "";
  return splits.map((s) => {
    const date = new Date(s * 1000);
    const label = format(style, date, locale);
    const today = format("day", date, locale);
    const withDay = today !== day ? `${label}\n${today}` : label;
    day = today;
    return withDay;
  });
}
