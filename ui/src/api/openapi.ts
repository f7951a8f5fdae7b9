// Generated from the server's /openapi.json by ui/scripts/api-types.mjs (npm run api-types,
// make ui-types): do not edit. Convenient names for these types are in types.ts.

export interface paths {
    "/api/v1/library": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Assets the caller may read, by scope, kind and name */
        get: operations["list_assets_api_v1_library_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/library/{scope}/{kind}/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** An asset with its versions, newest first */
        get: operations["get_asset_api_v1_library__scope___kind___name__get"];
        put?: never;
        post?: never;
        /** Delete an asset with all its versions (409 while one is in use) */
        delete: operations["delete_asset_api_v1_library__scope___kind___name__delete"];
        options?: never;
        head?: never;
        /** Change an asset's description, keywords, licence or author */
        patch: operations["update_asset_api_v1_library__scope___kind___name__patch"];
        trace?: never;
    };
    "/api/v1/library/{scope}/{kind}/{name}/versions": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The asset's versions, newest first (without their files) */
        get: operations["list_versions_api_v1_library__scope___kind___name__versions_get"];
        put?: never;
        /** Push a version: the body is the archive (tar, tgz, zip) or one file, streamed; 201 when new, 200 when a version with the same content existed (its tags are set) */
        post: operations["push_version_api_v1_library__scope___kind___name__versions_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/library/{scope}/{kind}/{name}/versions/{ref}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A version (a tag, a digest or a digest prefix of 12+ hex) with its files */
        get: operations["get_version_api_v1_library__scope___kind___name__versions__ref__get"];
        put?: never;
        post?: never;
        /** Delete a version (409 while a processor or deployment uses it) */
        delete: operations["delete_version_api_v1_library__scope___kind___name__versions__ref__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/library/{scope}/{kind}/{name}/versions/{ref}/archive": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A version as an archive, streamed */
        get: operations["get_archive_api_v1_library__scope___kind___name__versions__ref__archive_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/library/{scope}/{kind}/{name}/versions/{ref}/files/{path}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** One file of a version, streamed (always as a download) */
        get: operations["get_file_api_v1_library__scope___kind___name__versions__ref__files__path__get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/library/{scope}/{kind}/{name}/tags/{tag}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        /** Point a tag at a version (moved if it is set) */
        put: operations["set_tag_api_v1_library__scope___kind___name__tags__tag__put"];
        post?: never;
        /** Remove a tag (the version stays) */
        delete: operations["delete_tag_api_v1_library__scope___kind___name__tags__tag__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/healthz": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Liveness and store health (no token needed) */
        get: operations["healthz_healthz_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/readyz": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /**
         * Readiness for a load balancer: the store and the bus answer (no token needed)
         * @description 503 names what does not answer within TWINLINK_READY_TIMEOUT_S; never waits longer.
         */
        get: operations["readyz_readyz_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/metrics": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Prometheus metrics (text format): admins, or the metrics token (TWINLINK_METRICS_TOKEN) */
        get: operations["metrics_metrics_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/auth/login": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Exchange a username and password for a session token */
        post: operations["login_api_v1_auth_login_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/auth/logout": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Revoke the token this request was made with */
        post: operations["logout_api_v1_auth_logout_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/auth/me": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Who the caller is */
        get: operations["me_api_v1_auth_me_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/tokens": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The caller's API tokens (admins: everyone's with all=true) */
        get: operations["list_tokens_api_v1_tokens_get"];
        put?: never;
        /** Create an API token; the secret is shown once */
        post: operations["create_token_api_v1_tokens_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/users/{username}/tokens": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Create an API token for another user, e.g. a service account (admins) */
        post: operations["create_token_for_api_v1_users__username__tokens_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/tokens/{token_id}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        post?: never;
        /** Revoke an API token */
        delete: operations["revoke_token_api_v1_tokens__token_id__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/users": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** All users (admins) */
        get: operations["list_users_api_v1_users_get"];
        put?: never;
        /** Create a user (admins) */
        post: operations["create_user_api_v1_users_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/users/{username}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        post?: never;
        /** Delete a user (admins) */
        delete: operations["delete_user_api_v1_users__username__delete"];
        options?: never;
        head?: never;
        /** Change a user (admins; users may change their password) */
        patch: operations["update_user_api_v1_users__username__patch"];
        trace?: never;
    };
    "/api/v1/twins": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** List the twins the caller may see */
        get: operations["list_twins_api_v1_twins_get"];
        put?: never;
        /** Create a twin */
        post: operations["create_twin_api_v1_twins_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/apply": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Create or update twins from documents (idempotent) */
        post: operations["apply_api_v1_apply_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A twin and its document as the caller may see it */
        get: operations["get_twin_api_v1_twins__slug__get"];
        /** Update a twin's document parts */
        put: operations["update_twin_api_v1_twins__slug__put"];
        post?: never;
        /** Delete a twin (and, with cascade, its descendants) */
        delete: operations["delete_twin_api_v1_twins__slug__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/parts": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The privacy parts of a twin the caller may see */
        get: operations["list_parts_api_v1_twins__slug__parts_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/parts/{level}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** One privacy part, as stored (JSON, or YAML with format=yaml) */
        get: operations["get_part_api_v1_twins__slug__parts__level__get"];
        put?: never;
        post?: never;
        /** Remove one privacy part */
        delete: operations["delete_part_api_v1_twins__slug__parts__level__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/relations": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Descendants (down) or ancestors (up) to a depth */
        get: operations["relations_api_v1_twins__slug__relations_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/roles": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Who has which role on a twin */
        get: operations["list_roles_api_v1_twins__slug__roles_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/roles/{username}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        /** Grant a role (owners only) */
        put: operations["grant_role_api_v1_twins__slug__roles__username__put"];
        post?: never;
        /** Take a role away (owners only) */
        delete: operations["revoke_role_api_v1_twins__slug__roles__username__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/devices": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The devices of a twin, and `default_device`: where a command that names no device goes now (null: it must name one) (viewers) */
        get: operations["list_devices_api_v1_twins__slug__devices_get"];
        put?: never;
        /** Add a device (editors); its token is in the answer, once */
        post: operations["create_device_api_v1_twins__slug__devices_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/devices/{device}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** One device (viewers) */
        get: operations["get_device_api_v1_twins__slug__devices__device__get"];
        put?: never;
        post?: never;
        /** Remove a device and its token (editors) */
        delete: operations["delete_device_api_v1_twins__slug__devices__device__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/devices/{device}/token": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Replace a device's token (editors); the old one stops working */
        post: operations["rotate_device_token_api_v1_twins__slug__devices__device__token_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/device": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The device a device token belongs to (device tokens only) */
        get: operations["whoami_api_v1_device_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/device/samples": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Send a batch of samples (device token); the answer is its ack */
        post: operations["post_samples_api_v1_device_samples_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/streams": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's streams and their signals */
        get: operations["list_streams_api_v1_twins__slug__streams_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/streams/{stream}/latest": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The newest value of each signal of a stream */
        get: operations["latest_api_v1_twins__slug__streams__stream__latest_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/streams/{stream}/samples": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Stored samples in a time range, as rows joined on time, a page at a time */
        get: operations["samples_api_v1_twins__slug__streams__stream__samples_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/streams/{stream}/aggregate": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Aggregates (avg, min, max, count, first, last, sum) over fixed time buckets */
        get: operations["aggregate_api_v1_twins__slug__streams__stream__aggregate_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/streams/{stream}/downsample": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** At most `points` samples per signal that keep the peaks (minmax or lttb) */
        get: operations["downsample_api_v1_twins__slug__streams__stream__downsample_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/streams/{stream}/export": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The range as a CSV, JSON lines or JSON file, streamed */
        get: operations["export_api_v1_twins__slug__streams__stream__export_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/commands": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The command log of a twin, newest first (viewers) */
        get: operations["list_commands_api_v1_twins__slug__commands_get"];
        put?: never;
        /** Send a command to a device (editors); 200 when finished, 202 while underway */
        post: operations["send_command_api_v1_twins__slug__commands_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/commands/{command_id}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** One command and its state (viewers) */
        get: operations["get_command_api_v1_twins__slug__commands__command_id__get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/device/commands": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Pending commands for this device, waiting up to `wait` s; they count as delivered (device token) */
        get: operations["poll_commands_api_v1_device_commands_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/device/commands/{command_id}/result": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** The result of a command (device token) */
        post: operations["post_result_api_v1_device_commands__command_id__result_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/devices/{device}/properties": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Reported and desired properties of a device, and their delta (viewers) */
        get: operations["get_properties_api_v1_twins__slug__devices__device__properties_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/devices/{device}/properties/desired": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        /** Change desired properties (editors): name -> value, null removes one */
        patch: operations["patch_desired_api_v1_twins__slug__devices__device__properties_desired_patch"];
        trace?: never;
    };
    "/api/v1/device/properties": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** This device's properties: desired, delta and version (device token) */
        get: operations["device_properties_api_v1_device_properties_get"];
        put?: never;
        /** Report property values (device token); the answer has the desired delta */
        post: operations["report_properties_api_v1_device_properties_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/blueprints": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Blueprints with their documentation and parameter JSON schema */
        get: operations["list_blueprints_api_v1_blueprints_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/blueprints/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** One blueprint */
        get: operations["get_blueprint_api_v1_blueprints__name__get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/processors": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's processors with state and figures (viewers) */
        get: operations["list_processors_api_v1_twins__slug__processors_get"];
        put?: never;
        /** Create a processor (editors); it starts at once unless `enabled` is false */
        post: operations["create_processor_api_v1_twins__slug__processors_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/processors/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A processor: configuration, state, figures, its blueprint's inputs and outputs */
        get: operations["get_processor_api_v1_twins__slug__processors__name__get"];
        put?: never;
        post?: never;
        /** Delete (editors) */
        delete: operations["delete_processor_api_v1_twins__slug__processors__name__delete"];
        options?: never;
        head?: never;
        /** Change a processor (editors). New `params` alone are applied to the running worker, keeping its state where the blueprint can (`kept_state`); other changes restart it */
        patch: operations["update_processor_api_v1_twins__slug__processors__name__patch"];
        trace?: never;
    };
    "/api/v1/twins/{slug}/processors/{name}/start": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Start (editors) */
        post: operations["start_processor_api_v1_twins__slug__processors__name__start_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/processors/{name}/stop": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Stop gracefully (editors) */
        post: operations["stop_processor_api_v1_twins__slug__processors__name__stop_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/processors/{name}/restart": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Restart its worker (editors) */
        post: operations["restart_processor_api_v1_twins__slug__processors__name__restart_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/processors/{name}/events": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** What happened: started, crashed (with the cause), memory limit, alarms (newest first) */
        get: operations["processor_events_api_v1_twins__slug__processors__name__events_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/processors/{name}/logs": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The last lines its worker printed (its own and its native code's output) */
        get: operations["processor_logs_api_v1_twins__slug__processors__name__logs_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/fmus/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** An FMU and its variables: causality, type, unit, start, min, max (viewers) */
        get: operations["get_fmu_api_v1_twins__slug__fmus__name__get"];
        /** Upload an FMU (editors): the file as the body; checked with FMPy, replaced if it exists */
        put: operations["upload_fmu_api_v1_twins__slug__fmus__name__put"];
        post?: never;
        /** Delete an FMU (editors) */
        delete: operations["delete_fmu_api_v1_twins__slug__fmus__name__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/fmus": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's FMUs (viewers) */
        get: operations["list_fmus_api_v1_twins__slug__fmus_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/services": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's gateway services: features with an apiAddress and those added by API (viewers); credentials show only whether each secret is set */
        get: operations["list_services_api_v1_twins__slug__services_get"];
        put?: never;
        /** Add a service by API (owners): name, base_url, auth, methods, limits, health_path */
        post: operations["create_service_api_v1_twins__slug__services_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/services/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** One service (viewers) */
        get: operations["get_service_api_v1_twins__slug__services__name__get"];
        put?: never;
        post?: never;
        /** Delete a service added by API, or reset a document service's settings (owners) */
        delete: operations["delete_service_api_v1_twins__slug__services__name__delete"];
        options?: never;
        head?: never;
        /** Change a service's settings or credentials (owners). Secret fields left out of an `auth` of the same method are kept */
        patch: operations["update_service_api_v1_twins__slug__services__name__patch"];
        trace?: never;
    };
    "/api/v1/twins/{slug}/services/{name}/health": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Check the service now: a GET of its health_path (or base URL) with its credentials */
        get: operations["check_service_api_v1_twins__slug__services__name__health_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/gateway/audit": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Requests the gateway answered, newest first. Admins see all; others name a `twin` they own */
        get: operations["audit_api_v1_gateway_audit_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/service-accounts": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's service accounts (owners) */
        get: operations["list_accounts_api_v1_twins__slug__service_accounts_get"];
        put?: never;
        /** Make a service account for a feature that calls other services through the gateway (owners); its token is shown once */
        post: operations["create_account_api_v1_twins__slug__service_accounts_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/service-accounts/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        post?: never;
        /** Delete a service account and its tokens (owners) */
        delete: operations["delete_account_api_v1_twins__slug__service_accounts__name__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/connector-kinds": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The kinds of connector with their configuration's JSON schema */
        get: operations["list_kinds_api_v1_connector_kinds_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/connectors": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's connectors with settings (no secrets) and status (viewers) */
        get: operations["list_connectors_api_v1_twins__slug__connectors_get"];
        put?: never;
        /** Create a connector (admins); it starts at once unless `enabled` is false, and nothing is kept when it cannot start */
        post: operations["create_connector_api_v1_twins__slug__connectors_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/connectors/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A connector: settings (no secrets) and status (viewers) */
        get: operations["get_connector_api_v1_twins__slug__connectors__name__get"];
        put?: never;
        post?: never;
        /** Delete (admins) */
        delete: operations["delete_connector_api_v1_twins__slug__connectors__name__delete"];
        options?: never;
        head?: never;
        /** Change `config` (fields given; secrets left out are kept) or `enabled` (admins); it restarts with them, or nothing changes when it cannot start */
        patch: operations["update_connector_api_v1_twins__slug__connectors__name__patch"];
        trace?: never;
    };
    "/api/v1/twins/{slug}/connectors/{name}/start": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Enable and start (admins) */
        post: operations["start_connector_api_v1_twins__slug__connectors__name__start_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/connectors/{name}/stop": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Stop and disable (admins) */
        post: operations["stop_connector_api_v1_twins__slug__connectors__name__stop_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/twins/{slug}/connectors/{name}/restart": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Restart (admins) */
        post: operations["restart_connector_api_v1_twins__slug__connectors__name__restart_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/mqtt": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** MQTT: mode, address, state, connected devices and counts (admins) */
        get: operations["mqtt_status_api_v1_mqtt_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/deployments": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The deployments the caller may see (those of twins they see), newest first */
        get: operations["list_deployments_api_v1_deployments_get"];
        put?: never;
        /** Deploy a twin package: plan, then apply all or nothing (201), or only the plan (`dry_run`, 200) */
        post: operations["create_deployment_api_v1_deployments_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/deployments/{name}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A deployment: its package, parameters, state and what it made */
        get: operations["get_deployment_api_v1_deployments__name__get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        /** Reconfigure: new parameters (others kept) and/or package version; the diff plan, applied unless `dry_run` (unchanged resources are not touched) */
        patch: operations["change_deployment_api_v1_deployments__name__patch"];
        trace?: never;
    };
    "/api/v1/deployments/{name}/create": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Apply a planned deployment */
        post: operations["create_planned_api_v1_deployments__name__create_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/deployments/{name}/start": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Start: its processors and connectors run, and its `execute` phase */
        post: operations["start_deployment_api_v1_deployments__name__start_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/deployments/{name}/stop": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Stop: its processors and connectors stop, and a running `execute`; the twin stays */
        post: operations["stop_deployment_api_v1_deployments__name__stop_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/deployments/{name}/terminate": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Terminate: remove its devices (their tokens), processors, connectors and services; the twin and its history stay unless `purge` */
        post: operations["terminate_deployment_api_v1_deployments__name__terminate_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/deployments/{name}/runs": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The deployment's runs, newest first (all are kept) */
        get: operations["list_runs_api_v1_deployments__name__runs_get"];
        put?: never;
        /** Run a lifecycle phase of the deployment (its package's lifecycle/<phase>) */
        post: operations["start_run_api_v1_deployments__name__runs_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/runs/{run_id}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A run: its phase, state, exit code and times */
        get: operations["get_run_api_v1_runs__run_id__get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/runs/{run_id}/log": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The run's log (stdout and stderr) from byte `offset`, as far as it is written */
        get: operations["get_log_api_v1_runs__run_id__log_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/runs/{run_id}/cancel": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Cancel a run: its process group gets SIGTERM, then SIGKILL after 5 s */
        post: operations["cancel_run_api_v1_runs__run_id__cancel_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/cosims": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The caller's co-simulations (every one for admins), newest first */
        get: operations["list_cosims_api_v1_cosims_get"];
        put?: never;
        /** Create a co-simulation from a file or folder (the body); its FMUs resolve inside the folder, in the library (lib:...) or among the twin's uploaded FMUs */
        post: operations["create_cosim_api_v1_cosims_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/cosims/{cosim_id}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A co-simulation: its system, state and progress */
        get: operations["get_cosim_api_v1_cosims__cosim_id__get"];
        put?: never;
        post?: never;
        /** Delete a co-simulation with its files and results (409 while it runs) */
        delete: operations["delete_cosim_api_v1_cosims__cosim_id__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/cosims/{cosim_id}/start": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Run it (again: new results); the body may change its mode and factor */
        post: operations["start_cosim_api_v1_cosims__cosim_id__start_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/cosims/{cosim_id}/stop": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Stop its run after the current step (the rows so far kept) */
        post: operations["stop_cosim_api_v1_cosims__cosim_id__stop_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/cosims/{cosim_id}/results.csv": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The latest run's results as Maestro's outputs.csv (as far as written) */
        get: operations["results_csv_api_v1_cosims__cosim_id__results_csv_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/cosims/{cosim_id}/results": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The latest run's results for a chart: its columns, at most `max_points` rows picked evenly, column by column */
        get: operations["results_api_v1_cosims__cosim_id__results_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/federation/peers": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Origins of other instances this one has a token for (admins) */
        get: operations["list_peers_api_v1_federation_peers_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/federation/peers/{peer}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        /** Store the token sent to a peer (host[:port]) when fetching from it (admins) */
        put: operations["put_peer_api_v1_federation_peers__peer__put"];
        post?: never;
        /** Forget the token of a peer (admins) */
        delete: operations["delete_peer_api_v1_federation_peers__peer__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/resolve": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Fetch the twin a dt-id or URL of another instance names, now, and keep it */
        get: operations["resolve_api_v1_resolve_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/twins/{slug}/export.aasx": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin as an Asset Administration Shell package (AASX) */
        get: operations["twin_aasx_twins__slug__export_aasx_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/workspaces/me": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The caller's workspace: its state, a one-time link while it runs, the last log lines when it failed */
        get: operations["show_api_v1_workspaces_me_get"];
        put?: never;
        /** Start the caller's workspace (a no-op when it runs); answers once it answers, with a one-time link to it */
        post: operations["start_api_v1_workspaces_me_post"];
        /** Stop the caller's workspace (its files are kept, its token revoked) */
        delete: operations["stop_api_v1_workspaces_me_delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/workspaces": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Every workspace this server runs or ran (admins) */
        get: operations["list_all_api_v1_workspaces_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/workspaces/{user}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        post?: never;
        /** Stop a user's workspace (admins, or the user) */
        delete: operations["stop_user_api_v1_workspaces__user__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/search": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Find twins and the features that hold what you need */
        get: operations["search_api_v1_search_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/remote-twins": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** Remote twins: documents of other instances kept here, by name */
        get: operations["list_remote_twins_api_v1_remote_twins_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/remote-twins/{remote_id}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** A remote twin with its document */
        get: operations["get_remote_twin_api_v1_remote_twins__remote_id__get"];
        put?: never;
        post?: never;
        /** Forget a remote twin (a relation to it fetches it again) */
        delete: operations["delete_remote_twin_api_v1_remote_twins__remote_id__delete"];
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/remote-twins/import": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Mirror a Twinbase site (or another twinlink) as remote twins: its index.json, then each twin's document; importing again updates them */
        post: operations["import_remote_twins_api_v1_remote_twins_import_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/api/v1/remote-twins/{remote_id}/refresh": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        get?: never;
        put?: never;
        /** Fetch a remote twin again from where it was found (a 304 keeps the copy) */
        post: operations["refresh_remote_twin_api_v1_remote_twins__remote_id__refresh_post"];
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/twins/{slug}": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's DT document (YAML, JSON or HTML by Accept), or ?format= an export */
        get: operations["twin_document_twins__slug__get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/twins/{slug}/index.yaml": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's DT document as YAML (Twinbase's layout) */
        get: operations["twin_yaml_twins__slug__index_yaml_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/twins/{slug}/index.json": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's DT document as JSON (Twinbase's layout) */
        get: operations["twin_json_twins__slug__index_json_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/twins/{slug}/index.html": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The twin's page (Twinbase's layout) */
        get: operations["twin_html_twins__slug__index_html_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/index.yaml": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The site's twins in Twinbase's index shape (baseurl, owner, twins), as YAML */
        get: operations["site_yaml_index_yaml_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
    "/index.json": {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** The site's twins in Twinbase's index shape (baseurl, owner, twins), as JSON */
        get: operations["site_json_index_json_get"];
        put?: never;
        post?: never;
        delete?: never;
        options?: never;
        head?: never;
        patch?: never;
        trace?: never;
    };
}
export type webhooks = Record<string, never>;
export interface components {
    schemas: {
        /**
         * Ack
         * @description A batch's ack (docs/protocol.md): sent once the accepted samples are stored.
         */
        Ack: {
            /**
             * Type
             * @constant
             */
            type: "ack";
            /**
             * Seq
             * @description the batch's `seq`, as sent
             */
            seq: unknown;
            /** Accepted */
            accepted: number;
            /**
             * Rejected
             * @description the first samples refused, and why
             */
            rejected: {
                [key: string]: unknown;
            }[];
            /** Rejected Count */
            rejected_count: number;
            /**
             * Server Timed
             * @description samples without a time, timed by the server
             */
            server_timed: number;
            /** Dropped */
            dropped: number;
            /**
             * Duplicate
             * @description a batch already stored (same device and seq)
             */
            duplicate: boolean;
        };
        /** AggregateAnswer */
        AggregateAnswer: {
            /** Twin */
            twin: string;
            /** Stream */
            stream: string;
            /** Start */
            start: number | null;
            /** End */
            end: number | null;
            /**
             * Bucket
             * @description the bucket width, e.g. `1m`
             */
            bucket: string;
            /** Bucket Ns */
            bucket_ns: number;
            /** Fn */
            fn: string[];
            /** Rows */
            rows: components["schemas"]["AggregateRow"][];
            /**
             * Skipped
             * @description signals left out: they hold text
             */
            skipped: string[];
        };
        /** AggregateRow */
        AggregateRow: {
            /**
             * Time
             * @description the bucket's start
             */
            time: number;
            /**
             * Values
             * @description signal -> function -> value (sums of integers are exact integers)
             */
            values: {
                [key: string]: {
                    [key: string]: number | null;
                };
            };
        };
        /** AppliedList */
        AppliedList: {
            /**
             * Results
             * @description one per twin, in the documents' order
             */
            results: components["schemas"]["twinlink__api__models__twins__Applied"][];
        };
        /** AssetChange */
        AssetChange: {
            /** Description */
            description?: string | null;
            /** Keywords */
            keywords?: string[] | null;
            /** Licence */
            licence?: string | null;
            /** Author */
            author?: string | null;
        };
        /** AssetDetail */
        AssetDetail: {
            /**
             * Scope
             * @description common, group:<group> or user:<username>
             */
            scope: string;
            /**
             * Kind
             * @description data, models, tools, functions or twins
             */
            kind: string;
            /** Name */
            name: string;
            /**
             * Ref
             * @description <scope>/<kind>/<name>, as written after lib:
             */
            ref: string;
            /** Description */
            description: string;
            /** Keywords */
            keywords: string[];
            /** Licence */
            licence: string;
            /** Author */
            author: string;
            /**
             * Tags
             * @description tag -> version digest
             */
            tags: {
                [key: string]: string;
            };
            /**
             * Latest
             * @description the digest `latest` points at
             */
            latest: string | null;
            /**
             * Versions
             * @description newest first
             */
            versions: components["schemas"]["VersionSummary"][];
            /** Created By */
            created_by: string | null;
            /** Created Ns */
            created_ns: number;
            /** Updated Ns */
            updated_ns: number;
            /** Version Count */
            version_count: number;
        };
        /** AssetView */
        AssetView: {
            /**
             * Scope
             * @description common, group:<group> or user:<username>
             */
            scope: string;
            /**
             * Kind
             * @description data, models, tools, functions or twins
             */
            kind: string;
            /** Name */
            name: string;
            /**
             * Ref
             * @description <scope>/<kind>/<name>, as written after lib:
             */
            ref: string;
            /** Description */
            description: string;
            /** Keywords */
            keywords: string[];
            /** Licence */
            licence: string;
            /** Author */
            author: string;
            /**
             * Tags
             * @description tag -> version digest
             */
            tags: {
                [key: string]: string;
            };
            /**
             * Latest
             * @description the digest `latest` points at
             */
            latest: string | null;
            /**
             * Versions
             * @description how many versions it has
             */
            versions: number;
            /** Created By */
            created_by: string | null;
            /** Created Ns */
            created_ns: number;
            /** Updated Ns */
            updated_ns: number;
        };
        /** Assets */
        Assets: {
            /** Assets */
            assets: components["schemas"]["AssetView"][];
            /**
             * Next
             * @description pass as `after` for the next page; null on the last page
             */
            next: string | null;
        };
        /** AuditEntry */
        AuditEntry: {
            /** Id */
            id: number;
            /**
             * Time
             * @description Unix time in seconds
             */
            time: number;
            /** Time Iso */
            time_iso: string;
            /** Twin */
            twin: string;
            /** Service */
            service: string;
            /** Caller */
            caller: string;
            /** Method */
            method: string;
            /** Path */
            path: string;
            /** Status */
            status: number;
            /** Outcome */
            outcome: string;
            /** Bytes In */
            bytes_in: number;
            /** Bytes Out */
            bytes_out: number;
            /** Upstream Ms */
            upstream_ms: number | null;
            /** Total Ms */
            total_ms: number;
        };
        /** AuditPage */
        AuditPage: {
            /** Entries */
            entries: components["schemas"]["AuditEntry"][];
            /**
             * Next Before
             * @description `before` of the next page; null at the end
             */
            next_before: number | null;
        };
        /** Blueprint */
        Blueprint: {
            /** Name */
            name: string;
            /**
             * Source
             * @description `installed` (an entry point) or the file it came from
             */
            source: string;
            /** Title */
            title?: string | null;
            /** Description */
            description?: string | null;
            /**
             * Keeps State
             * @description new params keep the worker's state
             */
            keeps_state?: boolean | null;
            /**
             * Params Schema
             * @description its parameters' JSON schema
             */
            params_schema?: {
                [key: string]: unknown;
            } | null;
            /**
             * Error
             * @description why it cannot be loaded (then it is unusable)
             */
            error?: string | null;
        };
        /** Blueprints */
        Blueprints: {
            /** Blueprints */
            blueprints: components["schemas"]["Blueprint"][];
        };
        /** ChangeBody */
        ChangeBody: {
            /**
             * Parameters
             * @description those to change; others kept
             */
            parameters?: {
                [key: string]: unknown;
            } | null;
            /**
             * Package
             * @description another version of the package
             */
            package?: string | null;
        };
        /** CommandList */
        CommandList: {
            /** Commands */
            commands: components["schemas"]["CommandView"][];
        };
        /** CommandResult */
        CommandResult: {
            /**
             * Status
             * @enum {string}
             */
            status: "succeeded" | "failed";
            /**
             * Result
             * @description any JSON value
             */
            result?: unknown;
            /** Error */
            error?: string | null;
        };
        /** CommandView */
        CommandView: {
            /** Id */
            id: string;
            /** Twin */
            twin: string;
            /** Device */
            device: string;
            /** Name */
            name: string;
            /** Args */
            args: {
                [key: string]: unknown;
            };
            /**
             * State
             * @enum {string}
             */
            state: "pending" | "delivered" | "succeeded" | "failed" | "expired";
            /**
             * Queued
             * @description kept for a device that was offline
             */
            queued: boolean;
            /** Sent By */
            sent_by: string | null;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Expires
             * @description ISO 8601, UTC
             */
            expires: string;
            /** Delivered */
            delivered: string | null;
            /** Finished */
            finished: string | null;
            /**
             * Result
             * @description what the device answered (any JSON value)
             */
            result: unknown;
            /** Error */
            error: string | null;
            /**
             * Late Status
             * @description a result that came after it expired
             */
            late_status: string | null;
        };
        /** ConnectorKind */
        ConnectorKind: {
            /** Kind */
            kind: string;
            /** Description */
            description: string;
            /**
             * Schema
             * @description its config's JSON schema
             */
            schema: {
                [key: string]: unknown;
            };
            /** Secret Fields */
            secret_fields: string[];
        };
        /** ConnectorKinds */
        ConnectorKinds: {
            /** Kinds */
            kinds: components["schemas"]["ConnectorKind"][];
        };
        /** ConnectorStatus */
        ConnectorStatus: {
            /** State */
            state: string;
            /** Since Ns */
            since_ns: number;
            /**
             * Errors
             * @description kind of error -> count
             */
            errors: {
                [key: string]: number;
            };
            /** Error Count */
            error_count: number;
            /** Last Error */
            last_error: string | null;
            /** Last Error Ns */
            last_error_ns: number | null;
            /** Last Message Ns */
            last_message_ns: number | null;
            /** Messages */
            messages: number;
            /** Samples */
            samples: number;
            /** Rejected */
            rejected: number;
            /** Commands */
            commands: number;
            /**
             * Address
             * @description where it listens or what it reaches
             */
            address?: string | null;
        };
        /** ConnectorView */
        ConnectorView: {
            /** Name */
            name: string;
            /** Twin */
            twin: string;
            /** Kind */
            kind: string;
            /** Device */
            device: string;
            /** Enabled */
            enabled: boolean;
            /** Config */
            config: {
                [key: string]: unknown;
            };
            status: components["schemas"]["ConnectorStatus"];
            /** Created Ns */
            created_ns: number;
            /** Modified Ns */
            modified_ns: number;
        };
        /** Connectors */
        Connectors: {
            /** Connectors */
            connectors: components["schemas"]["ConnectorView"][];
        };
        /** Cosim */
        Cosim: {
            /** Id */
            id: number;
            /** Name */
            name: string;
            /** Owner */
            owner: string | null;
            /**
             * Twin
             * @description the twin whose history gets the results
             */
            twin: string | null;
            /**
             * Prefix
             * @description of the signals written into the twin's history
             */
            prefix: string;
            /**
             * Stream
             * @description the twin's stream they go to
             */
            stream: string;
            /**
             * Mode
             * @description batch or realtime
             */
            mode: string;
            /** Factor */
            factor: number;
            /**
             * State
             * @description created, running, finished, stopped or failed
             */
            state: string;
            /**
             * Progress
             * @description 0 to 1
             */
            progress: number;
            /** Sim Time */
            sim_time: number | null;
            /**
             * Message
             * @description why it failed or ended early
             */
            message: string;
            /** Created At */
            created_at: string;
            /** Started At */
            started_at: string | null;
            /** Ended At */
            ended_at: string | null;
            system: components["schemas"]["CosimSystem"];
            /**
             * Columns
             * @description the results' columns, time first
             */
            columns: string[];
            /** Rows */
            rows: number;
        };
        /** CosimAlgorithm */
        CosimAlgorithm: {
            /**
             * Kind
             * @description fixed-step or var-step
             */
            kind: string;
            /** Size */
            size: number;
            /** Min Size */
            min_size: number | null;
            /** Max Size */
            max_size: number | null;
            /**
             * Master
             * @description jacobi or gauss-seidel
             */
            master: string;
        };
        /** CosimConnection */
        CosimConnection: {
            /** Source */
            source: string;
            /** Target */
            target: string;
        };
        /** CosimInstance */
        CosimInstance: {
            /** Name */
            name: string;
            /** Fmu */
            fmu: string;
            /**
             * Kind
             * @description co-simulation, model-exchange or python
             */
            kind: string;
            /** Isolated */
            isolated: boolean;
        };
        /** CosimList */
        CosimList: {
            /** Cosims */
            cosims: components["schemas"]["Cosim"][];
        };
        /** CosimResults */
        CosimResults: {
            /** Columns */
            columns: string[];
            /**
             * Data
             * @description column by column (uPlot's shape)
             */
            data: (number | null)[][];
        };
        /** CosimStart */
        CosimStart: {
            /**
             * Mode
             * @description batch or realtime; the last one's if not given
             */
            mode?: string | null;
            /**
             * Factor
             * @description realtime: 1.0 = wall clock, 2.0 = twice as fast
             */
            factor?: number | null;
        };
        /** CosimSystem */
        CosimSystem: {
            /**
             * Source
             * @description the format it was read from: maestro, ssp or yaml
             */
            source: string;
            /** Instances */
            instances: components["schemas"]["CosimInstance"][];
            /** Connections */
            connections: components["schemas"]["CosimConnection"][];
            algorithm: components["schemas"]["CosimAlgorithm"];
            /** Start Time */
            start_time: number;
            /** End Time */
            end_time: number | null;
            /**
             * Loops
             * @description algebraic loops, each as its ports in order
             */
            loops: string[][];
        };
        /** CreateBody */
        CreateBody: {
            /**
             * Package
             * @description a `twins` asset: NAME[@REF], SCOPE/twins/NAME[@REF] or lib:
             */
            package: string;
            /**
             * Name
             * @description the deployment's and its twin's name (a slug)
             */
            name: string;
            /** Parameters */
            parameters?: {
                [key: string]: unknown;
            };
            /**
             * Scope
             * @description look the package up in this scope only
             */
            scope?: string | null;
            /**
             * Start
             * @description start it once created
             * @default false
             */
            start?: boolean;
            /**
             * State
             * @description `planned`: store it without applying it
             */
            state?: string | null;
        };
        /** DeletedDevice */
        DeletedDevice: {
            /**
             * Deleted
             * @description the device's name
             */
            deleted: string;
        };
        /** DeletedTwins */
        DeletedTwins: {
            /**
             * Deleted
             * @description the slugs deleted (the twin, and with cascade its descendants)
             */
            deleted: string[];
        };
        /** DeletedUser */
        DeletedUser: {
            /**
             * Deleted
             * @description the username
             */
            deleted: string;
        };
        /** Deployment */
        Deployment: {
            /** Id */
            id: number;
            /** Name */
            name: string;
            /**
             * Package
             * @description the pinned ref of the package version deployed
             */
            package: string;
            /**
             * Package Ref
             * @description the package as asked for
             */
            package_ref: string;
            /** Parameters */
            parameters: {
                [key: string]: unknown;
            };
            /**
             * State
             * @description planned, applying, created, running, stopped, terminated or failed
             */
            state: string;
            /** Twin */
            twin: string;
            resources: components["schemas"]["Resources"];
            /** Created By */
            created_by: string | null;
            /** Created Ns */
            created_ns: number;
            /** Updated Ns */
            updated_ns: number;
            /** Error */
            error: string | null;
        };
        /** DeploymentList */
        DeploymentList: {
            /** Deployments */
            deployments: components["schemas"]["Deployment"][];
        };
        /** DeviceList */
        DeviceList: {
            /** Devices */
            devices: components["schemas"]["DeviceState"][];
            /**
             * Default Device
             * @description where a command that names no device goes now; null: it must name one
             */
            default_device: string | null;
        };
        /** DeviceProperties */
        DeviceProperties: {
            /** Device */
            device: string;
            /** Reported */
            reported: {
                [key: string]: components["schemas"]["TimedProperty"];
            };
            /** Desired */
            desired: {
                [key: string]: components["schemas"]["TimedProperty"];
            };
            /**
             * Delta
             * @description desired values the device has not reported yet
             */
            delta: {
                [key: string]: unknown;
            };
            /**
             * Version
             * @description the version of the desired values
             */
            version: number;
        };
        /** DeviceState */
        DeviceState: {
            /** Name */
            name: string;
            /**
             * Twin
             * @description the slug of the device's twin
             */
            twin: string;
            /** Description */
            description: string;
            /**
             * Token Prefix
             * @description the token's first characters, to recognise it by
             */
            token_prefix: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Last Seen
             * @description ISO 8601, UTC; now while it is connected
             */
            last_seen: string | null;
            /**
             * Connected
             * @description whether it (or a connector speaking for it) has a session to this server
             */
            connected: boolean;
        };
        /** DeviceView */
        DeviceView: {
            /** Name */
            name: string;
            /**
             * Twin
             * @description the slug of the device's twin
             */
            twin: string;
            /** Description */
            description: string;
            /**
             * Token Prefix
             * @description the token's first characters, to recognise it by
             */
            token_prefix: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Last Seen
             * @description ISO 8601, UTC; now while it is connected
             */
            last_seen: string | null;
        };
        /** DeviceWithToken */
        DeviceWithToken: {
            /** Name */
            name: string;
            /**
             * Twin
             * @description the slug of the device's twin
             */
            twin: string;
            /** Description */
            description: string;
            /**
             * Token Prefix
             * @description the token's first characters, to recognise it by
             */
            token_prefix: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Last Seen
             * @description ISO 8601, UTC; now while it is connected
             */
            last_seen: string | null;
            /**
             * Token
             * @description the device token: shown in this answer only
             */
            token: string;
        };
        /** DownsampleAnswer */
        DownsampleAnswer: {
            /** Twin */
            twin: string;
            /** Stream */
            stream: string;
            /** Start */
            start: number | null;
            /** End */
            end: number | null;
            /**
             * Method
             * @enum {string}
             */
            method: "minmax" | "lttb";
            /** Points */
            points: number;
            /** Signals */
            signals: {
                [key: string]: components["schemas"]["Series"];
            };
            /**
             * Skipped
             * @description signals left out: they hold text
             */
            skipped: string[];
        };
        /** Facets */
        Facets: {
            /** Keywords */
            keywords: components["schemas"]["KeywordCount"][];
            /**
             * Counted Hits
             * @description how many of the first hits the facets count
             */
            counted_hits: number;
        };
        /** FileView */
        FileView: {
            /**
             * Path
             * @description the file's path inside the version ('/'-separated)
             */
            path: string;
            /** Sha256 */
            sha256: string;
            /** Size */
            size: number;
            /** Executable */
            executable: boolean;
        };
        /**
         * FmuView
         * @description An FMU and what FMPy read from it (`model_name`, `fmi_version`, ...); `variables`
         *     only for one FMU.
         */
        FmuView: {
            /** Name */
            name: string;
            /** Sha256 */
            sha256: string;
            /** Size */
            size: number;
            /** Uploaded Ns */
            uploaded_ns: number;
            /** Variables */
            variables?: {
                [key: string]: unknown;
            }[] | null;
        } & {
            [key: string]: unknown;
        };
        /** Fmus */
        Fmus: {
            /** Fmus */
            fmus: components["schemas"]["FmuView"][];
        };
        /** Health */
        Health: {
            /**
             * Checked At
             * @description Unix time in seconds
             */
            checked_at: number;
            /** Path */
            path: string | null;
            /**
             * Status
             * @enum {string}
             */
            status: "up" | "down";
            /** Http Status */
            http_status: number | null;
            /** Ms */
            ms: number;
            /** Error */
            error?: string | null;
        };
        /** Healthy */
        Healthy: {
            /**
             * Status
             * @constant
             */
            status: "ok";
            /** Version */
            version: string;
        };
        /** Hit */
        Hit: {
            /**
             * Kind
             * @description a twin, or a library asset
             * @enum {string}
             */
            kind: "twin" | "asset";
            /**
             * Slug
             * @description the twin's; null for an asset
             */
            slug: string | null;
            /** Name */
            name: string;
            /** Score */
            score: number;
            /** Matches */
            matches: components["schemas"]["Match"][];
            /**
             * Ref
             * @description an asset's <scope>/<kind>/<name>
             */
            ref?: string | null;
            /**
             * Scope
             * @description an asset's scope
             */
            scope?: string | null;
            /**
             * Asset Kind
             * @description an asset's kind: data, models, ...
             */
            asset_kind?: string | null;
            /**
             * Description
             * @description an asset's description
             */
            description?: string | null;
        };
        /** ImportFailure */
        ImportFailure: {
            /** Url */
            url: string;
            /** Name */
            name: string;
            /** Error */
            error: string;
        };
        /** ImportResult */
        ImportResult: {
            /** Source */
            source: string;
            /** Imported */
            imported: components["schemas"]["RemoteTwinSummary"][];
            /**
             * Failed
             * @description twins that could not be fetched, and why
             */
            failed: components["schemas"]["ImportFailure"][];
        };
        /** ImportSite */
        ImportSite: {
            /**
             * Url
             * @description The site's root (its index.json is read) or the URL of its index.json
             */
            url: string;
        };
        /**
         * InputMap
         * @description Where a blueprint input comes from: a signal of the source stream, scaled and offset
         *     (value * scale + offset; the thesis's `measurement_proportion` is the scale).
         */
        InputMap: {
            /**
             * Signal
             * @description signal of the source stream
             */
            signal: string;
            /**
             * Scale
             * @description multiplied with the value first
             * @default 1
             */
            scale?: number;
            /**
             * Offset
             * @description added after scaling
             * @default 0
             */
            offset?: number;
        };
        /** IssuedToken */
        IssuedToken: {
            /**
             * Token
             * @description the secret: shown in this answer only
             */
            token: string;
            /** Id */
            id: number;
            /** Name */
            name: string;
            /**
             * State
             * @enum {string}
             */
            state: "active" | "expired" | "revoked";
            /**
             * Prefix
             * @description the token's first characters, to recognise it by
             */
            prefix: string;
            /**
             * Kind
             * @description `api` (made by a person or script) or `session` (a login)
             */
            kind: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Expires
             * @description ISO 8601, UTC; null: it does not expire
             */
            expires: string | null;
            /** Last Used */
            last_used: string | null;
            /** Revoked */
            revoked: string | null;
        };
        /** IssuedTokenFor */
        IssuedTokenFor: {
            /**
             * Token
             * @description the secret: shown in this answer only
             */
            token: string;
            /**
             * Username
             * @description the user the token belongs to
             */
            username: string;
            /** Id */
            id: number;
            /** Name */
            name: string;
            /**
             * State
             * @enum {string}
             */
            state: "active" | "expired" | "revoked";
            /**
             * Prefix
             * @description the token's first characters, to recognise it by
             */
            prefix: string;
            /**
             * Kind
             * @description `api` (made by a person or script) or `session` (a login)
             */
            kind: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Expires
             * @description ISO 8601, UTC; null: it does not expire
             */
            expires: string | null;
            /** Last Used */
            last_used: string | null;
            /** Revoked */
            revoked: string | null;
        };
        /** KeywordCount */
        KeywordCount: {
            /** Value */
            value: string;
            /** Count */
            count: number;
        };
        /** Latest */
        Latest: {
            /** Twin */
            twin: string;
            /** Stream */
            stream: string;
            /**
             * Values
             * @description signal -> its newest value
             */
            values: {
                [key: string]: components["schemas"]["TimedValue"];
            };
        };
        /** ListedToken */
        ListedToken: {
            /** Id */
            id: number;
            /** Name */
            name: string;
            /**
             * State
             * @enum {string}
             */
            state: "active" | "expired" | "revoked";
            /**
             * Prefix
             * @description the token's first characters, to recognise it by
             */
            prefix: string;
            /**
             * Kind
             * @description `api` (made by a person or script) or `session` (a login)
             */
            kind: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Expires
             * @description ISO 8601, UTC; null: it does not expire
             */
            expires: string | null;
            /** Last Used */
            last_used: string | null;
            /** Revoked */
            revoked: string | null;
            /**
             * Username
             * @description the user the token belongs to
             */
            username: string;
            /**
             * Current
             * @description whether it is the token of this request
             */
            current: boolean;
        };
        /** LogLine */
        LogLine: {
            /** Time Ns */
            time_ns: number;
            /** Text */
            text: string;
        };
        /** Login */
        Login: {
            /** Username */
            username: string;
            /** Password */
            password: string;
        };
        /** LoginAnswer */
        LoginAnswer: {
            /**
             * Token
             * @description the secret: shown in this answer only
             */
            token: string;
            /**
             * Token Type
             * @constant
             */
            token_type: "bearer";
            /** Id */
            id: number;
            /** Name */
            name: string;
            /**
             * State
             * @enum {string}
             */
            state: "active" | "expired" | "revoked";
            /**
             * Prefix
             * @description the token's first characters, to recognise it by
             */
            prefix: string;
            /**
             * Kind
             * @description `api` (made by a person or script) or `session` (a login)
             */
            kind: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Expires
             * @description ISO 8601, UTC; null: it does not expire
             */
            expires: string | null;
            /** Last Used */
            last_used: string | null;
            /** Revoked */
            revoked: string | null;
        };
        /** Match */
        Match: {
            /**
             * Feature
             * @description the feature that matched; null: the twin itself
             */
            feature: string | null;
            /**
             * Privacy
             * @description the privacy part it is in
             */
            privacy: string;
            /**
             * Snippet
             * @description text around the match, the words in <mark>
             */
            snippet: string;
        };
        /** MqttStatus */
        MqttStatus: {
            /** State */
            state: string;
            /** Since Ns */
            since_ns: number;
            /** Errors */
            errors: {
                [key: string]: number;
            };
            /** Error Count */
            error_count: number;
            /** Last Error */
            last_error: string | null;
            /** Last Error Ns */
            last_error_ns: number | null;
            /** Mode */
            mode: ("embedded" | "external" | "off") | string;
            /** Address */
            address: string | null;
            /** Clients */
            clients: number;
            /** Connects */
            connects: number;
            /** Refused */
            refused: {
                [key: string]: number;
            };
            /** Messages */
            messages: number;
            /**
             * Received
             * @description messages by kind
             */
            received: {
                [key: string]: number;
            };
            /** Samples */
            samples: number;
            /** Sent */
            sent: number;
        };
        /** NewCommand */
        NewCommand: {
            /**
             * Name
             * @description a command of the twin's interface (any name if it has none)
             */
            name: string;
            /**
             * Args
             * @description argument name -> value
             */
            args?: {
                [key: string]: unknown;
            } | null;
            /**
             * Device
             * @description the device; may be left out if there is one
             */
            device?: string | null;
            /**
             * Timeout S
             * @description seconds until it expires [server default]
             */
            timeout_s?: number | null;
            /**
             * Queue
             * @description keep it for an offline device until it connects
             * @default false
             */
            queue?: boolean;
            /**
             * Wait
             * @description answer when it has finished, not at once
             * @default true
             */
            wait?: boolean;
        };
        /** NewDevice */
        NewDevice: {
            /**
             * Name
             * @description unique within the twin
             */
            name: string;
            /**
             * Description
             * @default
             */
            description?: string;
        };
        /** NewServiceAccount */
        NewServiceAccount: {
            /** Name */
            name: string;
            /** User */
            user: string;
            /** Role */
            role: string;
            /**
             * Token
             * @description its token: shown in this answer only
             */
            token: string;
            /** Token Prefix */
            token_prefix: string;
        };
        /** NewToken */
        NewToken: {
            /**
             * Name
             * @description what the token is for
             */
            name: string;
            /**
             * Expires In S
             * @description lifetime in seconds, at most 100 years; none = no expiry
             */
            expires_in_s?: number | null;
        };
        /** NewUser */
        NewUser: {
            /** Username */
            username: string;
            /** Password */
            password?: string | null;
            /**
             * Is Admin
             * @default false
             */
            is_admin?: boolean;
            /** Groups */
            groups?: string[];
        };
        /** Parts */
        Parts: {
            /** Levels */
            levels: string[];
        };
        /** PeerOrigins */
        PeerOrigins: {
            /**
             * Peers
             * @description Origins this instance has a token for.
             */
            peers: string[];
        };
        /** PeerStored */
        PeerStored: {
            /**
             * Origin
             * @description The origin the token is sent to, and only to it.
             */
            origin: string;
        };
        /** PeerToken */
        PeerToken: {
            /**
             * Token
             * @description A token of a service account on the peer; stored sealed, never shown.
             */
            token: string;
            /**
             * Scheme
             * @description The peer's scheme; http only on a network you trust.
             * @default https
             * @enum {string}
             */
            scheme?: "https" | "http";
        };
        /** PendingCommand */
        PendingCommand: {
            /** Id */
            id: string;
            /** Name */
            name: string;
            /** Args */
            args: {
                [key: string]: unknown;
            };
            /**
             * Expires
             * @description ns since the epoch
             */
            expires: number;
        };
        /** PendingCommands */
        PendingCommands: {
            /** Commands */
            commands: components["schemas"]["PendingCommand"][];
        };
        /** Percentiles */
        Percentiles: {
            /** P50 */
            p50: number | null;
            /** P99 */
            p99: number | null;
        };
        /** Plan */
        Plan: {
            /** Create */
            create: components["schemas"]["PlanEntry"][];
            /** Update */
            update: components["schemas"]["PlanEntry"][];
            /** Delete */
            delete: components["schemas"]["PlanEntry"][];
            /** Keep */
            keep: components["schemas"]["PlanEntry"][];
        };
        /** PlanAnswer */
        PlanAnswer: {
            plan: components["schemas"]["Plan"];
        };
        /** PlanEntry */
        PlanEntry: {
            /** Type */
            type: string;
            /** Name */
            name: string;
            /** Spec */
            spec?: {
                [key: string]: unknown;
            } | null;
            /** Changes */
            changes?: {
                [key: string]: unknown;
            }[] | null;
        };
        /**
         * Problem
         * @description An error answer (`application/problem+json`). `detail` is meant for a person: it says
         *     what to change. Some errors add fields: `errors` (what is wrong where), or `reason` and
         *     `devices` (a command that must name its device).
         */
        Problem: {
            /**
             * Type
             * @description always `about:blank`: the status says it
             * @default about:blank
             */
            type?: string;
            /**
             * Title
             * @description the status's name, e.g. `Not found`
             */
            title: string;
            /** Status */
            status: number;
            /** Detail */
            detail: string;
            /** Errors */
            errors?: components["schemas"]["ProblemItem"][] | null;
            /** Reason */
            reason?: string | null;
            /** Devices */
            devices?: string[] | null;
        } & {
            [key: string]: unknown;
        };
        /**
         * ProblemItem
         * @description One thing wrong with the request: where (a parameter's path, or a document's line)
         *     and what.
         */
        ProblemItem: {
            /** Message */
            message: string;
            /**
             * Path
             * @description e.g. `query.limit` or `features[0].name`
             */
            path?: string | null;
            /**
             * Line
             * @description the line in a DT document, from 1
             */
            line?: number | null;
            /**
             * Column
             * @description the column in a DT document, from 1
             */
            column?: number | null;
            /**
             * Document
             * @description which document of a stream, from 0
             */
            document?: number | null;
        };
        /** ProcessorEvent */
        ProcessorEvent: {
            /** Id */
            id: number;
            /** Time Ns */
            time_ns: number;
            /** Kind */
            kind: string;
            /** Message */
            message: string;
            /** Data */
            data: {
                [key: string]: unknown;
            };
        };
        /** ProcessorEvents */
        ProcessorEvents: {
            /** Events */
            events: components["schemas"]["ProcessorEvent"][];
        };
        /** ProcessorLogs */
        ProcessorLogs: {
            /** Lines */
            lines: components["schemas"]["LogLine"][];
        };
        /**
         * ProcessorSpec
         * @description What a processor runs, on what, and where its results go.
         */
        ProcessorSpec: {
            /**
             * Name
             * @description unique within the twin; also the default output stream
             */
            name: string;
            /**
             * Blueprint
             * @description a blueprint name from /api/v1/blueprints
             */
            blueprint: string;
            /**
             * Source
             * @description the twin's stream the processor reads
             * @default telemetry
             */
            source?: string;
            /**
             * Output
             * @description the stream it writes [its name]
             */
            output?: string | null;
            /**
             * Inputs
             * @description blueprint input -> source signal (a name, or {signal, scale, offset}); inputs left out read the source signal of the same name
             */
            inputs?: {
                [key: string]: components["schemas"]["InputMap"] | string;
            };
            /**
             * Params
             * @description the blueprint's parameters
             */
            params?: {
                [key: string]: unknown;
            };
            rates?: components["schemas"]["Rates"];
            /**
             * Python Requirements
             * @description pip requirements (`more-itertools==10.7.0`) of a Python FMU: the worker runs in a virtualenv of its own made from them (docs/processors.md) [none: the server's Python]
             */
            python_requirements?: string[];
            /**
             * Memory Limit Mb
             * @description the worker is restarted when its RSS is above this
             * @default 1024
             */
            memory_limit_mb?: number;
            /**
             * Batch Timeout S
             * @description a worker stuck this long on one batch is restarted
             * @default 30
             */
            batch_timeout_s?: number;
            /**
             * Enabled
             * @description whether it runs (now and after a server restart)
             * @default true
             */
            enabled?: boolean;
        };
        /** ProcessorStats */
        ProcessorStats: {
            /** Samples In */
            samples_in: number;
            /** Samples Out */
            samples_out: number;
            /** Batches */
            batches: number;
            /** Dropped */
            dropped: number;
            /** Restarts */
            restarts: number;
            /** Crashes */
            crashes: number;
            /** Rss Bytes */
            rss_bytes: number;
            step_time_s: components["schemas"]["Percentiles"];
            added_latency_s: components["schemas"]["Percentiles"];
        };
        /** ProcessorView */
        ProcessorView: {
            /** Name */
            name: string;
            /** Twin */
            twin: string;
            /** Blueprint */
            blueprint: string;
            /**
             * Source
             * @description the stream it reads
             */
            source: string;
            /**
             * Output
             * @description the stream it writes (null: its own name)
             */
            output: string | null;
            /** Inputs */
            inputs: {
                [key: string]: components["schemas"]["InputMap"] | string;
            };
            /** Params */
            params: {
                [key: string]: unknown;
            };
            rates: components["schemas"]["Rates"];
            /**
             * Python Requirements
             * @description pip requirements of its own Python env, if any
             */
            python_requirements?: string[];
            /** Memory Limit Mb */
            memory_limit_mb: number;
            /** Batch Timeout S */
            batch_timeout_s: number;
            /** Enabled */
            enabled: boolean;
            /**
             * State
             * @description starting, running, backoff, stopping, stopped, failed or finished (the model ended its simulation; started again by restart or update)
             */
            state: string;
            /** Pid */
            pid: number | null;
            /** Last Error */
            last_error: string | null;
            /**
             * Restart At
             * @description Unix time (s) of the next start (backoff)
             */
            restart_at: number | null;
            stats: components["schemas"]["ProcessorStats"] | null;
            /**
             * Running
             * @description what the running worker says of itself
             */
            running: {
                [key: string]: unknown;
            };
            /** Created Ns */
            created_ns: number;
            /** Modified Ns */
            modified_ns: number;
            /**
             * Kept State
             * @description only in answers to a change: whether the worker kept its state
             */
            kept_state?: boolean | null;
        };
        /** Processors */
        Processors: {
            /** Processors */
            processors: components["schemas"]["ProcessorView"][];
        };
        /** PushAnswer */
        PushAnswer: {
            asset: components["schemas"]["AssetView"];
            version: components["schemas"]["VersionView"];
            /**
             * Created
             * @description false: a version with the same content existed
             */
            created: boolean;
        };
        /**
         * Rates
         * @description Rate limits like the Tvilling digital platform's, plus batching.
         */
        Rates: {
            /**
             * Min Input Spacing S
             * @description input samples closer than this to the last one used are skipped
             * @default 0
             */
            min_input_spacing_s?: number;
            /**
             * Min Step Spacing S
             * @description shortest time between steps, for blueprints that step
             * @default 0
             */
            min_step_spacing_s?: number;
            /**
             * Min Output Spacing S
             * @description output samples closer than this to the last one sent are dropped
             * @default 0
             */
            min_output_spacing_s?: number;
            /**
             * Max Batch
             * @description most samples handed to the blueprint at once
             * @default 10000
             */
            max_batch?: number;
        };
        /**
         * Ready
         * @description The store answered its ping and the bus is usable, within TWINLINK_READY_TIMEOUT_S.
         */
        Ready: {
            /**
             * Status
             * @constant
             */
            status: "ready";
            /** Version */
            version: string;
        };
        /**
         * RelationNode
         * @description A twin in a relation tree; a related id that is not registered here has
         *     `registered: false` and no slug or name, and `remote` when it is another instance's
         *     twin (an http(s) dt-id).
         */
        RelationNode: {
            /** Id */
            id: string;
            /** Slug */
            slug?: string | null;
            /** Name */
            name?: string | null;
            /** Registered */
            registered?: boolean | null;
            remote?: components["schemas"]["RemoteSummary"] | null;
            /** Nodes */
            nodes: components["schemas"]["RelationNode"][];
        };
        /**
         * RemoteHit
         * @description A remote twin (another instance's, kept here read-only) whose text holds the query.
         */
        RemoteHit: {
            /**
             * Remote Id
             * @description its id under /api/v1/remote-twins
             */
            remote_id: number;
            /** Dt Id */
            dt_id: string;
            /** Name */
            name: string;
            /**
             * Url
             * @description where its document is (its hosting-iri)
             */
            url: string;
            /**
             * State
             * @description reachable, stale or gone
             */
            state: string;
        };
        /**
         * RemoteSummary
         * @description A twin of another instance a relation names (docs/federation.md).
         */
        RemoteSummary: {
            /**
             * Url
             * @description Where the document was fetched (its hosting-iri).
             */
            url: string;
            /** Name */
            name: string;
            /**
             * State
             * @description reachable, stale or gone; pending (not fetched yet) or refused (by the SSRF guard) when no copy is kept.
             */
            state: string;
            /**
             * Fetched At
             * @description When the copy was fetched (RFC 3339, UTC).
             */
            fetched_at: string | null;
            /**
             * Remote Id
             * @description The remote twin (/api/v1/remote-twins).
             */
            remote_id?: number | null;
        };
        /** RemoteTwinList */
        RemoteTwinList: {
            /** Remote Twins */
            remote_twins: components["schemas"]["RemoteTwinSummary"][];
        };
        /** RemoteTwinSummary */
        RemoteTwinSummary: {
            /** Id */
            id: number;
            /**
             * Dt Id
             * @description the document's dt-id (or id), else the URL it came from
             */
            dt_id: string;
            /**
             * Url
             * @description where the document was fetched: its hosting-iri
             */
            url: string;
            /** Name */
            name: string;
            /**
             * Source
             * @description the site imported, or `relation`
             */
            source: string;
            /**
             * State
             * @description reachable, stale (the last check failed or is old) or gone
             */
            state: string;
            /**
             * Error
             * @description why the last check failed
             */
            error: string;
            /**
             * Fetched At
             * @description when the copy was fetched
             */
            fetched_at: string;
            /**
             * Checked At
             * @description when the other instance was last asked
             */
            checked_at: string;
        };
        /** RemoteTwinView */
        RemoteTwinView: {
            /** Id */
            id: number;
            /**
             * Dt Id
             * @description the document's dt-id (or id), else the URL it came from
             */
            dt_id: string;
            /**
             * Url
             * @description where the document was fetched: its hosting-iri
             */
            url: string;
            /** Name */
            name: string;
            /**
             * Source
             * @description the site imported, or `relation`
             */
            source: string;
            /**
             * State
             * @description reachable, stale (the last check failed or is old) or gone
             */
            state: string;
            /**
             * Error
             * @description why the last check failed
             */
            error: string;
            /**
             * Fetched At
             * @description when the copy was fetched
             */
            fetched_at: string;
            /**
             * Checked At
             * @description when the other instance was last asked
             */
            checked_at: string;
            /** Etag */
            etag: string | null;
            /** Last Modified */
            last_modified: string | null;
            /**
             * Document
             * @description the DT document as fetched, read-only
             */
            document: {
                [key: string]: unknown;
            };
        };
        /** ReportAck */
        ReportAck: {
            /** Version */
            version: number;
            /**
             * Desired
             * @description the delta: desired values still to apply
             */
            desired: {
                [key: string]: unknown;
            };
        };
        /** Resolved */
        Resolved: {
            /** Id */
            id: string;
            remote: components["schemas"]["RemoteSummary"];
        };
        /** Resources */
        Resources: {
            /** Twin */
            twin: string | null;
            /** Devices */
            devices: string[];
            /** Processors */
            processors: string[];
            /** Connectors */
            connectors: string[];
            /** Services */
            services: string[];
        };
        /** ResultAck */
        ResultAck: {
            /** Id */
            id: string;
            /**
             * State
             * @enum {string}
             */
            state: "pending" | "delivered" | "succeeded" | "failed" | "expired";
            /** Late Status */
            late_status: string | null;
        };
        /** Revoked */
        Revoked: {
            /**
             * Revoked
             * @description the id of the token revoked
             */
            revoked: number;
        };
        /** RoleBody */
        RoleBody: {
            /**
             * Role
             * @description one of owner, editor, viewer
             * @enum {string}
             */
            role: "owner" | "editor" | "viewer";
        };
        /** RoleChange */
        RoleChange: {
            /** Username */
            username: string;
            /**
             * Role
             * @description null when the role was taken away
             */
            role: ("owner" | "editor" | "viewer") | null;
        };
        /** RoleGrant */
        RoleGrant: {
            /** Username */
            username: string;
            /**
             * Role
             * @enum {string}
             */
            role: "owner" | "editor" | "viewer";
        };
        /** Roles */
        Roles: {
            /** Roles */
            roles: components["schemas"]["RoleGrant"][];
        };
        /** Row */
        Row: {
            /** Time */
            time: number;
            /**
             * Values
             * @description signal -> value at this time
             */
            values: {
                [key: string]: unknown;
            };
        };
        /** Run */
        Run: {
            /** Id */
            id: number;
            /** Deployment */
            deployment: string;
            /** Twin */
            twin: string;
            /** Phase */
            phase: string;
            /**
             * State
             * @description queued, running, succeeded, failed or cancelled
             */
            state: string;
            /**
             * Exit Code
             * @description negative: killed by that signal
             */
            exit_code: number | null;
            /** Started By */
            started_by: string | null;
            /** Created Ns */
            created_ns: number;
            /** Started Ns */
            started_ns: number | null;
            /** Ended Ns */
            ended_ns: number | null;
            /** Node */
            node: string | null;
            /** Error */
            error: string | null;
            /** Timeout S */
            timeout_s: number;
            /** Memory Mb */
            memory_mb: number;
            /** Runner Tags */
            runner_tags: string[];
        };
        /** RunList */
        RunList: {
            /** Runs */
            runs: components["schemas"]["Run"][];
        };
        /** SamplesPage */
        SamplesPage: {
            /** Twin */
            twin: string;
            /** Stream */
            stream: string;
            /** Start */
            start: number | null;
            /** End */
            end: number | null;
            /** Rows */
            rows: components["schemas"]["Row"][];
            /**
             * Next Cursor
             * @description `cursor` of the next page; null at the end
             */
            next_cursor: string | null;
        };
        /** SearchAnswer */
        SearchAnswer: {
            /** Query */
            query: string;
            /** Keyword */
            keyword: string | null;
            /** Total */
            total: number;
            /** Limit */
            limit: number;
            /** Offset */
            offset: number;
            /** Hits */
            hits: components["schemas"]["Hit"][];
            facets: components["schemas"]["Facets"];
            /**
             * Remote
             * @description remote twins that match, when asked for (remote=true) or configured
             */
            remote?: components["schemas"]["RemoteHit"][] | null;
        };
        /** Series */
        Series: {
            /** Time */
            time: number[];
            /** Value */
            value: number[];
        };
        /** ServiceAccount */
        ServiceAccount: {
            /** Name */
            name: string;
            /** User */
            user: string;
            /** Role */
            role: string;
            /** User Id */
            user_id: number;
        };
        /** ServiceAccountList */
        ServiceAccountList: {
            /** Service Accounts */
            service_accounts: components["schemas"]["ServiceAccount"][];
        };
        /**
         * ServiceAuth
         * @description How the gateway signs in to the service: `method`, and its settings (a secret only as
         *     `<name>_set`: whether it is set).
         */
        ServiceAuth: {
            /** Method */
            method: string;
        } & {
            [key: string]: unknown;
        };
        /** ServiceDeleted */
        ServiceDeleted: {
            /** Service */
            service: string;
            /**
             * Outcome
             * @description `deleted`, or `reset` for a service of the document
             */
            outcome: string;
        };
        /** ServiceHealth */
        ServiceHealth: {
            /**
             * Checked At
             * @description Unix time in seconds
             */
            checked_at: number;
            /** Path */
            path: string | null;
            /**
             * Status
             * @enum {string}
             */
            status: "up" | "down";
            /** Http Status */
            http_status: number | null;
            /** Ms */
            ms: number;
            /** Error */
            error?: string | null;
            /** Service */
            service: string;
        };
        /** ServiceStats */
        ServiceStats: {
            /**
             * Statuses
             * @description HTTP status -> answers
             */
            statuses: {
                [key: string]: number;
            };
            /**
             * Failures
             * @description kind of failure -> count
             */
            failures: {
                [key: string]: number;
            };
            /** Bytes In */
            bytes_in: number;
            /** Bytes Out */
            bytes_out: number;
            upstream_ms: components["schemas"]["UpstreamMs"] | null;
        };
        /** ServiceView */
        ServiceView: {
            /** Name */
            name: string;
            /** Twin */
            twin: string;
            /**
             * Source
             * @enum {string}
             */
            source: "document" | "api";
            /** Base Url */
            base_url: string;
            /** Feature */
            feature: string | null;
            /** Description */
            description: string | null;
            auth: components["schemas"]["ServiceAuth"];
            /** Methods */
            methods: string[];
            /** Limits */
            limits: {
                [key: string]: number;
            };
            /** Health Path */
            health_path: string | null;
            /** Websocket */
            websocket: boolean;
            /** Tls */
            tls: {
                [key: string]: unknown;
            };
            /**
             * Blocked
             * @description why the gateway does not forward to it, if so
             */
            blocked: string | null;
            /** Gateway Path */
            gateway_path: string;
            health: components["schemas"]["Health"] | null;
            /** Requests */
            requests: number;
            stats: components["schemas"]["ServiceStats"];
            /** Credential Refreshes */
            credential_refreshes: number;
            /** Credential Error */
            credential_error: string | null;
        };
        /** Services */
        Services: {
            /** Services */
            services: components["schemas"]["ServiceView"][];
        };
        /** SignalInfo */
        SignalInfo: {
            /** Name */
            name: string;
            /**
             * Kind
             * @description what its values are; `mixed` for more than one kind
             * @enum {string}
             */
            kind: "integer" | "number" | "bool" | "string" | "mixed";
            /**
             * Values
             * @description how many values are stored
             */
            values: number;
            /**
             * Count
             * @description the same as `values` (kept for older clients)
             */
            count: number;
            /** First */
            first: number | null;
            /** Last */
            last: number | null;
        };
        /** StartBody */
        StartBody: {
            /**
             * Phase
             * @description the lifecycle script to run: lifecycle/<phase>
             */
            phase: string;
        };
        /** StreamInfo */
        StreamInfo: {
            /** Name */
            name: string;
            /**
             * Samples
             * @description how many samples (times) are stored
             */
            samples: number;
            /**
             * Values
             * @description how many values, over all signals
             */
            values: number;
            /**
             * Count
             * @description the same as `values` (kept for older clients)
             */
            count: number;
            /** First */
            first: number | null;
            /** Last */
            last: number | null;
            /** Signals */
            signals: components["schemas"]["SignalInfo"][];
        };
        /** StreamList */
        StreamList: {
            /** Twin */
            twin: string;
            /** Streams */
            streams: components["schemas"]["StreamInfo"][];
        };
        /** TagBody */
        TagBody: {
            /**
             * Version
             * @description a tag, a digest or a digest prefix
             */
            version: string;
        };
        /** TerminateBody */
        TerminateBody: {
            /**
             * Purge
             * @description delete the twin too, with its history
             * @default false
             */
            purge?: boolean;
        };
        /** TimedProperty */
        TimedProperty: {
            /** Value */
            value: unknown;
            /**
             * Time
             * @description ISO 8601, UTC
             */
            time: string;
        };
        /** TimedValue */
        TimedValue: {
            /** Time */
            time: number;
            /**
             * Value
             * @description a number, bool or string
             */
            value: unknown;
        };
        /** TokenList */
        TokenList: {
            /** Tokens */
            tokens: components["schemas"]["ListedToken"][];
        };
        /** Twin */
        Twin: {
            /**
             * Slug
             * @description the twin's name in URLs
             */
            slug: string;
            /**
             * Id
             * @description the DT document's `id` (or `dt-id`): the twin's global id
             */
            id: string;
            /** Name */
            name: string;
            /**
             * Url
             * @description the canonical URL of the twin's document
             */
            url: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Modified
             * @description ISO 8601, UTC
             */
            modified: string;
            /**
             * Levels
             * @description privacy parts (of those the caller may see)
             */
            levels: string[];
            /**
             * Role
             * @description the caller's role on the twin (`admin` for platform admins)
             */
            role: ("owner" | "editor" | "viewer" | "admin") | null;
            /**
             * Document
             * @description the DT document: the parts the caller may see, merged
             */
            document: {
                [key: string]: unknown;
            };
        };
        /** TwinPage */
        TwinPage: {
            /** Items */
            items: components["schemas"]["TwinSummary"][];
            /**
             * Next Cursor
             * @description `cursor` of the next page; null at the end
             */
            next_cursor: string | null;
        };
        /** TwinSummary */
        TwinSummary: {
            /**
             * Slug
             * @description the twin's name in URLs
             */
            slug: string;
            /**
             * Id
             * @description the DT document's `id` (or `dt-id`): the twin's global id
             */
            id: string;
            /** Name */
            name: string;
            /**
             * Url
             * @description the canonical URL of the twin's document
             */
            url: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Modified
             * @description ISO 8601, UTC
             */
            modified: string;
            /**
             * Levels
             * @description privacy parts (of those the caller may see)
             */
            levels: string[];
        };
        /** Updated */
        Updated: {
            /**
             * Slug
             * @description the twin's name in URLs
             */
            slug: string;
            /**
             * Id
             * @description the DT document's `id` (or `dt-id`): the twin's global id
             */
            id: string;
            /** Name */
            name: string;
            /**
             * Url
             * @description the canonical URL of the twin's document
             */
            url: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Modified
             * @description ISO 8601, UTC
             */
            modified: string;
            /**
             * Levels
             * @description privacy parts (of those the caller may see)
             */
            levels: string[];
            /**
             * Outcome
             * @enum {string}
             */
            outcome: "created" | "updated" | "unchanged";
            /**
             * Dry Run
             * @description only with dry_run=true: the documents were checked, nothing stored
             */
            dry_run?: true | null;
        };
        /** UpstreamMs */
        UpstreamMs: {
            /** Mean */
            mean: number;
            /** P50 */
            p50: number | null;
            /** P95 */
            p95: number | null;
        };
        /** UserChange */
        UserChange: {
            /** Password */
            password?: string | null;
            /**
             * Current Password
             * @description the password you have now; needed to change your own password, unless you have none
             */
            current_password?: string | null;
            /** Is Admin */
            is_admin?: boolean | null;
            /** Groups */
            groups?: string[] | null;
            /** Disabled */
            disabled?: boolean | null;
        };
        /** UserList */
        UserList: {
            /** Users */
            users: components["schemas"]["UserView"][];
        };
        /** UserView */
        UserView: {
            /** Username */
            username: string;
            /** Is Admin */
            is_admin: boolean;
            /** Groups */
            groups: string[];
            /** Disabled */
            disabled: boolean;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
        };
        /** VersionSummary */
        VersionSummary: {
            /**
             * Digest
             * @description sha256: and the hex digest of the version's manifest
             */
            digest: string;
            /**
             * Size
             * @description bytes of all its files
             */
            size: number;
            /** File Count */
            file_count: number;
            /**
             * Meta
             * @description `fmus`: each FMU's FMI description, by path
             */
            meta: {
                [key: string]: unknown;
            };
            /** Tags */
            tags: string[];
            /** Created Ns */
            created_ns: number;
            /** Created By */
            created_by: string | null;
        };
        /** VersionView */
        VersionView: {
            /**
             * Digest
             * @description sha256: and the hex digest of the version's manifest
             */
            digest: string;
            /**
             * Size
             * @description bytes of all its files
             */
            size: number;
            /** File Count */
            file_count: number;
            /**
             * Meta
             * @description `fmus`: each FMU's FMI description, by path
             */
            meta: {
                [key: string]: unknown;
            };
            /** Tags */
            tags: string[];
            /** Created Ns */
            created_ns: number;
            /** Created By */
            created_by: string | null;
            /** Files */
            files: components["schemas"]["FileView"][];
        };
        /** Versions */
        Versions: {
            /** Versions */
            versions: components["schemas"]["VersionSummary"][];
        };
        /** WorkspaceView */
        WorkspaceView: {
            /** User */
            user: string;
            /**
             * State
             * @description starting, running, stopping, stopped or failed
             */
            state: string;
            /**
             * Url
             * @description /workspaces/<user>/?ticket=...: the workspace's address with a one-time ticket (valid 60 s) that the proxy swaps for a session cookie; only while it runs, and only in answers to its owner
             */
            url?: string | null;
            /** Started Ns */
            started_ns?: number | null;
            /**
             * Idle S
             * @description seconds since its last proxied traffic
             */
            idle_s?: number | null;
            /**
             * Error
             * @description why it failed
             */
            error?: string | null;
            /**
             * Log
             * @description the last lines of its log, when it failed
             */
            log: string[];
        };
        /** Workspaces */
        Workspaces: {
            /** Workspaces */
            workspaces: components["schemas"]["WorkspaceView"][];
        };
        /** Applied */
        twinlink__api__deployments__Applied: {
            deployment: components["schemas"]["Deployment"];
            plan: components["schemas"]["Plan"];
            /**
             * Device Tokens
             * @description new devices' tokens, shown once
             */
            device_tokens: {
                [key: string]: string;
            };
        };
        /** Applied */
        twinlink__api__models__twins__Applied: {
            /**
             * Slug
             * @description the twin's name in URLs
             */
            slug: string;
            /**
             * Id
             * @description the DT document's `id` (or `dt-id`): the twin's global id
             */
            id: string;
            /** Name */
            name: string;
            /**
             * Url
             * @description the canonical URL of the twin's document
             */
            url: string;
            /**
             * Created
             * @description ISO 8601, UTC
             */
            created: string;
            /**
             * Modified
             * @description ISO 8601, UTC
             */
            modified: string;
            /**
             * Levels
             * @description privacy parts (of those the caller may see)
             */
            levels: string[];
            /**
             * Outcome
             * @enum {string}
             */
            outcome: "created" | "updated" | "unchanged";
        };
    };
    responses: never;
    parameters: never;
    requestBodies: never;
    headers: never;
    pathItems: never;
}
export type $defs = Record<string, never>;
export interface operations {
    list_assets_api_v1_library_get: {
        parameters: {
            query?: {
                kind?: string | null;
                scope?: string | null;
                /** @description words in name, text */
                q?: string | null;
                limit?: number;
                /** @description the last asset's ref */
                after?: string | null;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Assets"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_asset_api_v1_library__scope___kind___name__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["AssetDetail"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_asset_api_v1_library__scope___kind___name__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    update_asset_api_v1_library__scope___kind___name__patch: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["AssetChange"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["AssetView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_versions_api_v1_library__scope___kind___name__versions_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Versions"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    push_version_api_v1_library__scope___kind___name__versions_post: {
        parameters: {
            query?: {
                /** @description tar, tgz, zip or file */
                format?: string;
                /** @description format=file: the file's name */
                filename?: string | null;
                /** @description tags to point at it */
                tag?: string[] | null;
                /** @description false: leave `latest` where it is */
                latest?: boolean;
            };
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/octet-stream": string;
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["PushAnswer"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The body is larger than the server takes */
            413: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_version_api_v1_library__scope___kind___name__versions__ref__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
                ref: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["VersionView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_version_api_v1_library__scope___kind___name__versions__ref__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
                ref: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_archive_api_v1_library__scope___kind___name__versions__ref__archive_get: {
        parameters: {
            query?: {
                format?: "tar" | "tgz" | "zip";
            };
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
                ref: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/x-tar": string;
                    "application/gzip": string;
                    "application/zip": string;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_file_api_v1_library__scope___kind___name__versions__ref__files__path__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
                ref: string;
                path: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/octet-stream": string;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    set_tag_api_v1_library__scope___kind___name__tags__tag__put: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
                tag: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["TagBody"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["AssetView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_tag_api_v1_library__scope___kind___name__tags__tag__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                scope: string;
                kind: string;
                name: string;
                tag: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    healthz_healthz_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Healthy"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    readyz_readyz_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Ready"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    metrics_metrics_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "text/plain": string;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    login_api_v1_auth_login_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["Login"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["LoginAnswer"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    logout_api_v1_auth_logout_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Revoked"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    me_api_v1_auth_me_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["UserView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_tokens_api_v1_tokens_get: {
        parameters: {
            query?: {
                all?: boolean;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["TokenList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_token_api_v1_tokens_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["NewToken"];
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["IssuedToken"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_token_for_api_v1_users__username__tokens_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                username: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["NewToken"];
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["IssuedTokenFor"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    revoke_token_api_v1_tokens__token_id__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                token_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Revoked"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_users_api_v1_users_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["UserList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_user_api_v1_users_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["NewUser"];
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["UserView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_user_api_v1_users__username__delete: {
        parameters: {
            query?: {
                force?: boolean;
            };
            header?: never;
            path: {
                username: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeletedUser"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    update_user_api_v1_users__username__patch: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                username: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["UserChange"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["UserView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_twins_api_v1_twins_get: {
        parameters: {
            query?: {
                limit?: number;
                /** @description `next_cursor` of the previous page */
                cursor?: string | null;
                /** @description only twins with a feature of this keyword */
                keyword?: string | null;
                /** @description only twins whose name contains this text */
                q?: string | null;
                /** @description only twins the caller has a role on */
                mine?: boolean;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["TwinPage"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_twin_api_v1_twins_post: {
        parameters: {
            query?: {
                /** @description slug to use instead of the derived one */
                slug?: string | null;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** @description A DT document, or several (a YAML stream with `---`, or a JSON list): the parts of one twin split by privacy, or several twins. */
        requestBody: {
            content: {
                "application/yaml": string;
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["twinlink__api__models__twins__Applied"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The body is larger than the server takes */
            413: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    apply_api_v1_apply_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** @description A DT document, or several (a YAML stream with `---`, or a JSON list): the parts of one twin split by privacy, or several twins. */
        requestBody: {
            content: {
                "application/yaml": string;
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["AppliedList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The body is larger than the server takes */
            413: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_twin_api_v1_twins__slug__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Twin"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    update_twin_api_v1_twins__slug__put: {
        parameters: {
            query?: {
                /** @description check the documents and the rights; store nothing */
                dry_run?: boolean;
            };
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        /** @description A DT document, or several (a YAML stream with `---`, or a JSON list): the parts of one twin split by privacy, or several twins. */
        requestBody: {
            content: {
                "application/yaml": string;
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Updated"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The body is larger than the server takes */
            413: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_twin_api_v1_twins__slug__delete: {
        parameters: {
            query?: {
                /** @description also delete every descendant */
                cascade?: boolean;
            };
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeletedTwins"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_parts_api_v1_twins__slug__parts_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Parts"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_part_api_v1_twins__slug__parts__level__get: {
        parameters: {
            query?: {
                /** @description answer format */
                format?: "json" | "yaml";
            };
            header?: never;
            path: {
                slug: string;
                level: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": {
                        [key: string]: unknown;
                    };
                    "application/yaml": Record<string, never>;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_part_api_v1_twins__slug__parts__level__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                level: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["TwinSummary"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    relations_api_v1_twins__slug__relations_get: {
        parameters: {
            query?: {
                direction?: "down" | "up";
                depth?: number;
            };
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["RelationNode"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_roles_api_v1_twins__slug__roles_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Roles"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    grant_role_api_v1_twins__slug__roles__username__put: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                username: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["RoleBody"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["RoleChange"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    revoke_role_api_v1_twins__slug__roles__username__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                username: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["RoleChange"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_devices_api_v1_twins__slug__devices_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_device_api_v1_twins__slug__devices_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["NewDevice"];
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceWithToken"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_device_api_v1_twins__slug__devices__device__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                device: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceState"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_device_api_v1_twins__slug__devices__device__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                device: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeletedDevice"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    rotate_device_token_api_v1_twins__slug__devices__device__token_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                device: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceWithToken"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    whoami_api_v1_device_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    post_samples_api_v1_device_samples_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    seq: number;
                    stream?: string;
                    /** @enum {unknown} */
                    time_unit?: "ns" | "us" | "ms" | "s";
                    samples: {
                        time?: number | string;
                        values: Record<string, never>;
                    }[];
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Ack"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The body is larger than the server takes */
            413: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_streams_api_v1_twins__slug__streams_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["StreamList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    latest_api_v1_twins__slug__streams__stream__latest_get: {
        parameters: {
            query?: {
                /** @description Comma-separated signal names; every signal when left out. */
                signals?: string | null;
            };
            header?: never;
            path: {
                slug: string;
                stream: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Latest"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    samples_api_v1_twins__slug__streams__stream__samples_get: {
        parameters: {
            query?: {
                /** @description Comma-separated signal names; every signal when left out. */
                signals?: string | null;
                /** @description From this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                start?: string | null;
                /** @description To this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                end?: string | null;
                /** @description Most rows in this page. */
                limit?: number;
                /** @description `next_cursor` of the previous page. */
                cursor?: string | null;
            };
            header?: never;
            path: {
                slug: string;
                stream: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["SamplesPage"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    aggregate_api_v1_twins__slug__streams__stream__aggregate_get: {
        parameters: {
            query?: {
                /** @description Bucket width, aligned to the epoch: a number and a unit: ns, us, ms, s, m, h, d or w (`500ms`, `1s`, `15m`, `1.5h`). */
                bucket?: string;
                /** @description Comma-separated functions of avg, min, max, count, first, last, sum; default avg. */
                fn?: string | null;
                /** @description Comma-separated signal names; every signal when left out. */
                signals?: string | null;
                /** @description From this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                start?: string | null;
                /** @description To this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                end?: string | null;
            };
            header?: never;
            path: {
                slug: string;
                stream: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["AggregateAnswer"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    downsample_api_v1_twins__slug__streams__stream__downsample_get: {
        parameters: {
            query?: {
                /** @description Most samples per signal. */
                points?: number;
                /** @description minmax (each bucket's min and max) or lttb (largest triangle). */
                method?: string | null;
                /** @description Comma-separated signal names; every signal when left out. */
                signals?: string | null;
                /** @description From this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                start?: string | null;
                /** @description To this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                end?: string | null;
            };
            header?: never;
            path: {
                slug: string;
                stream: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DownsampleAnswer"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    export_api_v1_twins__slug__streams__stream__export_get: {
        parameters: {
            query?: {
                /** @description csv (default), jsonl or json. */
                format?: string | null;
                /** @description iso (ISO 8601 UTC with ns; default for csv) or ns (default else). */
                time?: string | null;
                /** @description Comma-separated signal names; every signal when left out. */
                signals?: string | null;
                /** @description From this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                start?: string | null;
                /** @description To this time (inclusive): ISO 8601 (`2026-11-21T10:00:00.5Z`; without a zone it is UTC), integer ns since the epoch (`1732200000000000000`), `now`, or back from now (`-90s`, `-15m`, `-1h`, `-7d`). */
                end?: string | null;
            };
            header?: never;
            path: {
                slug: string;
                stream: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description The file */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "text/csv": string;
                    "application/jsonl": string;
                    "application/json": string;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_commands_api_v1_twins__slug__commands_get: {
        parameters: {
            query?: {
                /** @description one of pending, delivered, succeeded, failed, expired */
                state?: string | null;
                /** @description only commands of this name */
                name?: string | null;
                /** @description only commands to this device */
                device?: string | null;
                limit?: number;
            };
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["CommandList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    send_command_api_v1_twins__slug__commands_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["NewCommand"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["CommandView"];
                };
            };
            /** @description Sent (or queued) and not finished yet: poll its id */
            202: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["CommandView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_command_api_v1_twins__slug__commands__command_id__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                command_id: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["CommandView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    poll_commands_api_v1_device_commands_get: {
        parameters: {
            query?: {
                /** @description seconds to wait */
                wait?: number;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["PendingCommands"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    post_result_api_v1_device_commands__command_id__result_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                command_id: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["CommandResult"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ResultAck"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_properties_api_v1_twins__slug__devices__device__properties_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                device: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceProperties"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    patch_desired_api_v1_twins__slug__devices__device__properties_desired_patch: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                device: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceProperties"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    device_properties_api_v1_device_properties_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeviceProperties"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    report_properties_api_v1_device_properties_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ReportAck"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_blueprints_api_v1_blueprints_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Blueprints"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_blueprint_api_v1_blueprints__name__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Blueprint"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_processors_api_v1_twins__slug__processors_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Processors"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_processor_api_v1_twins__slug__processors_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["ProcessorSpec"];
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_processor_api_v1_twins__slug__processors__name__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_processor_api_v1_twins__slug__processors__name__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    update_processor_api_v1_twins__slug__processors__name__patch: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    start_processor_api_v1_twins__slug__processors__name__start_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    stop_processor_api_v1_twins__slug__processors__name__stop_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    restart_processor_api_v1_twins__slug__processors__name__restart_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    processor_events_api_v1_twins__slug__processors__name__events_get: {
        parameters: {
            query?: {
                limit?: number;
                /** @description only entries with a smaller id (the last page's) */
                before?: number | null;
                /** @description only events of this kind */
                kind?: string | null;
            };
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorEvents"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    processor_logs_api_v1_twins__slug__processors__name__logs_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ProcessorLogs"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_fmu_api_v1_twins__slug__fmus__name__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["FmuView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    upload_fmu_api_v1_twins__slug__fmus__name__put: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/octet-stream": string;
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["FmuView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The body is larger than the server takes */
            413: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_fmu_api_v1_twins__slug__fmus__name__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_fmus_api_v1_twins__slug__fmus_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Fmus"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_services_api_v1_twins__slug__services_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Services"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_service_api_v1_twins__slug__services_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ServiceView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_service_api_v1_twins__slug__services__name__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ServiceView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_service_api_v1_twins__slug__services__name__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ServiceDeleted"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    update_service_api_v1_twins__slug__services__name__patch: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ServiceView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    check_service_api_v1_twins__slug__services__name__health_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ServiceHealth"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    audit_api_v1_gateway_audit_get: {
        parameters: {
            query?: {
                twin?: string | null;
                service?: string | null;
                /** @description the caller's username */
                user?: string | null;
                method?: string | null;
                /** @description an HTTP status code */
                status?: number | null;
                /** @description Unix time in seconds, 0 to 9223372036 (2262) */
                since?: number | null;
                /** @description Unix time in seconds, 0 to 9223372036 (2262) */
                until?: number | null;
                limit?: number;
                /** @description only entries with a smaller id (the last page's) */
                before?: number | null;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["AuditPage"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_accounts_api_v1_twins__slug__service_accounts_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ServiceAccountList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_account_api_v1_twins__slug__service_accounts_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["NewServiceAccount"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_account_api_v1_twins__slug__service_accounts__name__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_kinds_api_v1_connector_kinds_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ConnectorKinds"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_connectors_api_v1_twins__slug__connectors_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Connectors"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_connector_api_v1_twins__slug__connectors_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ConnectorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_connector_api_v1_twins__slug__connectors__name__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ConnectorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_connector_api_v1_twins__slug__connectors__name__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    update_connector_api_v1_twins__slug__connectors__name__patch: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": {
                    [key: string]: unknown;
                };
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ConnectorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    start_connector_api_v1_twins__slug__connectors__name__start_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ConnectorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    stop_connector_api_v1_twins__slug__connectors__name__stop_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ConnectorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    restart_connector_api_v1_twins__slug__connectors__name__restart_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ConnectorView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    mqtt_status_api_v1_mqtt_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["MqttStatus"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_deployments_api_v1_deployments_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["DeploymentList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_deployment_api_v1_deployments_post: {
        parameters: {
            query?: {
                /** @description answer the plan only; nothing is stored or changed */
                dry_run?: boolean;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["CreateBody"];
            };
        };
        responses: {
            /** @description The plan (`dry_run`) */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["PlanAnswer"];
                };
            };
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["twinlink__api__deployments__Applied"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_deployment_api_v1_deployments__name__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Deployment"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    change_deployment_api_v1_deployments__name__patch: {
        parameters: {
            query?: {
                /** @description answer the plan only; nothing is stored or changed */
                dry_run?: boolean;
            };
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["ChangeBody"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["twinlink__api__deployments__Applied"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_planned_api_v1_deployments__name__create_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["twinlink__api__deployments__Applied"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    start_deployment_api_v1_deployments__name__start_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Deployment"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    stop_deployment_api_v1_deployments__name__stop_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Deployment"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    terminate_deployment_api_v1_deployments__name__terminate_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody?: {
            content: {
                "application/json": components["schemas"]["TerminateBody"] | null;
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Deployment"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_runs_api_v1_deployments__name__runs_get: {
        parameters: {
            query?: {
                /** @description only entries with a smaller id (the last page's) */
                before?: number | null;
                limit?: number;
            };
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["RunList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    start_run_api_v1_deployments__name__runs_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                name: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["StartBody"];
            };
        };
        responses: {
            /** @description Successful Response */
            202: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Run"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_run_api_v1_runs__run_id__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                run_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Run"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_log_api_v1_runs__run_id__log_get: {
        parameters: {
            query?: {
                /** @description the first byte */
                offset?: number;
            };
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                run_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "text/plain": string;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    cancel_run_api_v1_runs__run_id__cancel_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                run_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Run"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_cosims_api_v1_cosims_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["CosimList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    create_cosim_api_v1_cosims_post: {
        parameters: {
            query?: {
                /** @description its name */
                name?: string | null;
                /** @description results into this twin's history (editors) */
                twin?: string | null;
                /** @description batch or realtime */
                mode?: string;
                /** @description realtime: 1.0 = wall clock */
                factor?: number;
                /** @description of the signals */
                prefix?: string;
                /** @description the twin's stream (default cosim) */
                stream?: string | null;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        /** @description The co-simulation file: a Maestro multi-model (JSON), twinlink's YAML form, an SSP archive (a zip with SystemStructure.ssd at its root), or a folder as a zip, tar or tgz holding one .json/.yaml document at its top level beside its FMUs. */
        requestBody: {
            content: {
                "application/json": string;
                "application/yaml": string;
                "application/x-yaml": string;
                "text/yaml": string;
                "application/zip": string;
                "application/x-zip-compressed": string;
                "application/x-tar": string;
                "application/gzip": string;
                "application/x-gzip": string;
            };
        };
        responses: {
            /** @description Successful Response */
            201: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Cosim"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The body is larger than the server takes */
            413: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The disk is full: nothing was stored; try again once space is freed */
            507: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_cosim_api_v1_cosims__cosim_id__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                cosim_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Cosim"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_cosim_api_v1_cosims__cosim_id__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                cosim_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    start_cosim_api_v1_cosims__cosim_id__start_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                cosim_id: number;
            };
            cookie?: never;
        };
        requestBody?: {
            content: {
                "application/json": components["schemas"]["CosimStart"] | null;
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Cosim"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    stop_cosim_api_v1_cosims__cosim_id__stop_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                cosim_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Cosim"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    results_csv_api_v1_cosims__cosim_id__results_csv_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                cosim_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "text/csv": string;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    results_api_v1_cosims__cosim_id__results_get: {
        parameters: {
            query?: {
                max_points?: number;
            };
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                cosim_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["CosimResults"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_peers_api_v1_federation_peers_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["PeerOrigins"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    put_peer_api_v1_federation_peers__peer__put: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                peer: string;
            };
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["PeerToken"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["PeerStored"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_peer_api_v1_federation_peers__peer__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                peer: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    resolve_api_v1_resolve_get: {
        parameters: {
            query: {
                /** @description a dt-id or URL */
                id: string;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Resolved"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The other instance could not be read */
            502: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    twin_aasx_twins__slug__export_aasx_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/asset-administration-shell-package+xml": string;
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    show_api_v1_workspaces_me_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["WorkspaceView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    start_api_v1_workspaces_me_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["WorkspaceView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The change conflicts with what is stored (a name taken, a thing in use) */
            409: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    stop_api_v1_workspaces_me_delete: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_all_api_v1_workspaces_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["Workspaces"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    stop_user_api_v1_workspaces__user__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                user: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    search_api_v1_search_get: {
        parameters: {
            query?: {
                /** @description words; each matches as a prefix */
                q?: string;
                /** @description facet filter */
                keyword?: string | null;
                limit?: number;
                offset?: number;
                /** @description also remote twins (docs/federation.md); default: TWINLINK_FEDERATION_SEARCH */
                remote?: boolean | null;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["SearchAnswer"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    list_remote_twins_api_v1_remote_twins_get: {
        parameters: {
            query?: {
                /** @description only those whose text holds this */
                q?: string | null;
            };
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["RemoteTwinList"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    get_remote_twin_api_v1_remote_twins__remote_id__get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                remote_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["RemoteTwinView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    delete_remote_twin_api_v1_remote_twins__remote_id__delete: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                remote_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            204: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    import_remote_twins_api_v1_remote_twins_import_post: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody: {
            content: {
                "application/json": components["schemas"]["ImportSite"];
            };
        };
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["ImportResult"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Another instance could not be read (unreachable, too slow, not a document) */
            502: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    refresh_remote_twin_api_v1_remote_twins__remote_id__refresh_post: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                /** @description the id (1 to 2^63-1) */
                remote_id: number;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": components["schemas"]["RemoteTwinView"];
                };
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description The token is valid, but its user may not do this */
            403: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Another instance could not be read (unreachable, too slow, not a document) */
            502: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    twin_document_twins__slug__get: {
        parameters: {
            query?: {
                /** @description The format, whatever Accept asks: yaml, json, html, or the document converted: wot-td (a W3C WoT Thing Description 1.1), dtdl (a DTDL v3 Interface), aas-json (an Asset Administration Shell environment). */
                format?: string | null;
            };
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/yaml": {
                        [key: string]: unknown;
                    };
                    "application/json": {
                        [key: string]: unknown;
                    };
                    "text/html": string;
                    "application/td+json": {
                        [key: string]: unknown;
                    };
                    "application/ld+json": {
                        [key: string]: unknown;
                    };
                };
            };
            /** @description Not Modified: the ETag in If-None-Match is current */
            304: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description Permanent Redirect: the twin whose id is this URL has a new slug */
            308: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    twin_yaml_twins__slug__index_yaml_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/yaml": {
                        [key: string]: unknown;
                    };
                };
            };
            /** @description Not Modified: the ETag in If-None-Match is current */
            304: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description Permanent Redirect: the twin whose id is this URL has a new slug */
            308: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    twin_json_twins__slug__index_json_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": {
                        [key: string]: unknown;
                    };
                };
            };
            /** @description Not Modified: the ETag in If-None-Match is current */
            304: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description Permanent Redirect: the twin whose id is this URL has a new slug */
            308: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    twin_html_twins__slug__index_html_get: {
        parameters: {
            query?: never;
            header?: never;
            path: {
                slug: string;
            };
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "text/html": string;
                };
            };
            /** @description Not Modified: the ETag in If-None-Match is current */
            304: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description Permanent Redirect: the twin whose id is this URL has a new slug */
            308: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description A parameter or the body is not valid; `errors` says where */
            422: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    site_yaml_index_yaml_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/yaml": {
                        baseurl: string;
                        owner: {
                            [key: string]: unknown;
                        };
                        twins: {
                            url: string;
                            name: string;
                        }[];
                    };
                };
            };
            /** @description Not Modified: the ETag in If-None-Match is current */
            304: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
    site_json_index_json_get: {
        parameters: {
            query?: never;
            header?: never;
            path?: never;
            cookie?: never;
        };
        requestBody?: never;
        responses: {
            /** @description Successful Response */
            200: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/json": {
                        baseurl: string;
                        owner: {
                            [key: string]: unknown;
                        };
                        twins: {
                            url: string;
                            name: string;
                        }[];
                    };
                };
            };
            /** @description Not Modified: the ETag in If-None-Match is current */
            304: {
                headers: {
                    [name: string]: unknown;
                };
                content?: never;
            };
            /** @description No token, or a token that is not valid (expired, revoked, unknown) */
            401: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description There is no such thing, or the caller may not see it */
            404: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
            /** @description Storage failed or a read ran over its time budget; try again (Retry-After) */
            503: {
                headers: {
                    [name: string]: unknown;
                };
                content: {
                    "application/problem+json": components["schemas"]["Problem"];
                };
            };
        };
    };
}
