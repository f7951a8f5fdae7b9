import { useCallback, useState } from "react";
import { sendCommand, type CommandRecord, type NewCommand } from "../../api/commands";
import { forThisPage } from "./deviceChoice";

/** Where and how the commands of the tab are sent; shared by every command form. */
export interface SendTarget {
  /** The device; left out only when the twin has none (the server says so). */
  device?: string;
  /** Why nothing can be sent yet (a device must be chosen), if so. */
  missing?: string;
  /** Keep the command for an offline device until it connects (then answered at once). */
  queue: boolean;
  /** Seconds until it expires; left out for the server's default. */
  timeoutS?: number;
}

/** Send commands from one form and keep the latest answer or error. */
export function useSendCommand(slug: string, target: SendTarget, onSent: () => void) {
  const [record, setRecord] = useState<CommandRecord>();
  const [error, setError] = useState<Error>();
  const [sending, setSending] = useState(false);

  const send = useCallback(
    async (name: string, args: Record<string, unknown>) => {
      if (target.missing) {
        setRecord(undefined);
        setError(new Error(target.missing));
        return;
      }
      const command: NewCommand = { name, args };
      if (target.device) command.device = target.device;
      if (target.timeoutS !== undefined) command.timeout_s = target.timeoutS;
      if (target.queue) {
        // A queued command may wait long for its device: answer at once and poll it.
        command.queue = true;
        command.wait = false;
      }
      setSending(true);
      setError(undefined);
      try {
        setRecord(await sendCommand(slug, command));
        onSent();
      } catch (err) {
        setRecord(undefined);
        setError(forThisPage(err));
      } finally {
        setSending(false);
      }
    },
    [slug, target.device, target.missing, target.queue, target.timeoutS, onSent],
  );

  return { record, setRecord, error, setError, sending, send };
}
