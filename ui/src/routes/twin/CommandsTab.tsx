import { Empty } from "../../components/common/Status";
import { useTwin } from "./context";

export function CommandsTab() {
  const { twin } = useTwin();
  return <Empty>Commands of {twin.name}: coming soon.</Empty>;
}
