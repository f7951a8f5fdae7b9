import { useOutletContext } from "react-router-dom";
import type { Twin } from "../../api/types";

/** What the twin page hands to each of its tabs. */
export interface TwinContext {
  slug: string;
  twin: Twin;
  /** Load the twin again (after its document changed). */
  reload: () => void;
}

export function useTwin(): TwinContext {
  return useOutletContext<TwinContext>();
}

/** Whether the caller may change the twin (send commands, edit, create processors). */
export function canEdit(twin: Twin): boolean {
  return twin.role === "owner" || twin.role === "editor" || twin.role === "admin";
}
