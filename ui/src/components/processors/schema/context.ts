import { createContext, useContext } from "react";
import type { JsonSchema } from "../../../api/processors";

/** What every field of one generated form shares. */
export interface SchemaFormContext {
  /** The whole schema, for $ref lookups. */
  root: JsonSchema;
  /** Server messages by dotted path. */
  errors: Record<string, string>;
  /** Signal names offered in fields that name a signal. */
  suggestions: string[];
  /** The id of the datalist holding `suggestions`. */
  suggestionsId: string;
  /** A field tells whether its text is unusable (JSON that does not parse...). */
  markInvalid: (path: string, invalid: boolean) => void;
}

export const FormContext = createContext<SchemaFormContext | null>(null);

export function useFormContext(): SchemaFormContext {
  const context = useContext(FormContext);
  if (!context) throw new Error("a schema field must be inside a SchemaForm");
  return context;
}

/** Whether a property names a signal of the source stream (so its input suggests them). */
export function namesSignal(key: string, schema: JsonSchema): boolean {
  return /signal/i.test(key) || /^the signals? /i.test(schema.description ?? "");
}
