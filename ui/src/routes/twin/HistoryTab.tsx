import { Empty } from "../../components/common/Status";
import { useTwin } from "./context";

export function HistoryTab() {
  const { twin } = useTwin();
  return <Empty>History of {twin.name}: coming soon.</Empty>;
}
