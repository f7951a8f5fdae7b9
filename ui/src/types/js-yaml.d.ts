// The part of js-yaml 4 the app uses (the package ships no types of its own, and the app
// needs only `load`): twin.yaml is read in the browser to build a deployment's form.
declare module "js-yaml" {
  export interface LoadOptions {
    filename?: string;
    json?: boolean;
  }
  /** The one document in `text`; throws a YAMLException (an Error) naming line and column. */
  export function load(text: string, options?: LoadOptions): unknown;
}
