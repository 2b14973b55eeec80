// SPDX-License-Identifier: MPL-2.0
// tests/opcua/client.js - an OPC UA client for tests/integration/it_df1opcua.sh, on node-opcua
// (not asyncua, the library df1opcua is built on). One session, the steps in order, one line
// of output per result:
//   node client.js URL [mode=None|Sign|SignAndEncrypt] [pki=DIR] [user=NAME password=PW] STEP...
// STEP (NODE is "LINE.stationN.TAG", in df1opcua's namespace urn:libdf1:df1opcua):
//   browse:NODE             every child: "child NAME CLASS NODEID"
//   attrs:NODE              "attrs NODE DATATYPE VALUERANK DIMS ACCESSLEVEL USERACCESSLEVEL"
//   read:NODE               "read NODE STATUS VALUE SOURCETIMESTAMP_MS"
//   write:NODE:TYPE:VALUE   "write NODE STATUS" (VALUE a JSON value; TYPE Int16 Int32 Float Boolean String)
//   writes:NODE:TYPE:VALUE|NODE:TYPE:VALUE...  one Write request of several nodes, in that order:
//                           "write NODE STATUS" each, in the request's order
//   wait:NODE:STATUS:S      read every 100 ms until STATUS (a name), at most S seconds: "wait NODE STATUS"
//   waitval:NODE:JSON:S     read every 100 ms until the value is JSON, at most S seconds: "waitval NODE STATUS VALUE"
//   kill:PID:SIGNAL         send SIGNAL (SIGUSR1 ...) to PID, e.g. df1sim's: "kill PID SIGNAL"
//   sub:NODE:N:S            a monitored item (100 ms sampling): the first N notifications within S
//                           seconds (any later ones ignored), "sub NODE STATUS VALUE" each, then
//                           "subdone NODE COUNT" (COUNT < N when S ran out first)
// Exit 0 when every step ran (whatever the StatusCodes), 1 on a failure to connect or a session
// refused: "error MESSAGE" on stdout.
"use strict";
const path = require("path");
const ua = require("node-opcua-client");
const { OPCUACertificateManager } = require("node-opcua-certificate-manager");

const NSU = "urn:libdf1:df1opcua";
const args = process.argv.slice(2);
const url = args.shift();
const opt = {};
const steps = [];
for (const a of args) {
    const m = /^(mode|pki|user|password)=(.*)$/.exec(a);
    if (m) opt[m[1]] = m[2];
    else steps.push(a);
}

function show(v) {
    if (v === null || v === undefined) return "null";
    if (ArrayBuffer.isView(v)) v = Array.from(v);
    return JSON.stringify(v);
}

async function main() {
    const mode = ua.MessageSecurityMode[opt.mode || "None"];
    const certificateManager = new OPCUACertificateManager({
        rootFolder: opt.pki || path.join(process.env.TMPDIR || "/tmp", "df1opcua-test-client-pki"),
        automaticallyAcceptUnknownCertificate: true,
    });
    await certificateManager.initialize();
    const client = ua.OPCUAClient.create({
        applicationName: "df1opcua-test",
        applicationUri: "urn:df1opcua-test-client",
        endpointMustExist: false,
        securityMode: mode,
        securityPolicy: mode === ua.MessageSecurityMode.None ? ua.SecurityPolicy.None : ua.SecurityPolicy.Basic256Sha256,
        clientCertificateManager: certificateManager,
        connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
        requestedSessionTimeout: 20000,
    });
    let session;
    try {
        await client.connect(url);
        session = await client.createSession(opt.user ? { type: ua.UserTokenType.UserName, userName: opt.user,
            password: opt.password || "" } : undefined);
    } catch (e) {
        console.log("error " + e.message.split("\n")[0]);
        await client.disconnect().catch(() => {});
        return 1;
    }
    const ns = (await session.readNamespaceArray()).indexOf(NSU);
    const id = (n) => `ns=${ns};s=${n}`;
    // [NODE, TYPE, VALUE...] (VALUE's own ':' split too) -> a WriteValue of the Value attribute
    const writeValue = (w) => {
        const value = JSON.parse(w.slice(2).join(":"));
        return { nodeId: id(w[0]), attributeId: ua.AttributeIds.Value,
            value: { value: { dataType: ua.DataType[w[1]], value,
                arrayType: Array.isArray(value) ? ua.VariantArrayType.Array : ua.VariantArrayType.Scalar } } };
    };
    for (const step of steps) {
        const p = step.split(":");
        const op = p[0], node = p[1];
        if (op === "browse") {
            const r = await session.browse(id(node));
            for (const ref of r.references) {
                console.log(`child ${ref.browseName.name} ${ua.NodeClass[ref.nodeClass]} ${ref.nodeId.toString()}`);
            }
        } else if (op === "attrs") {
            const A = ua.AttributeIds;
            const r = await session.read([A.DataType, A.ValueRank, A.ArrayDimensions, A.AccessLevel, A.UserAccessLevel]
                .map((attributeId) => ({ nodeId: id(node), attributeId })));
            const dt = r[0].value.value;
            const dtName = dt && dt.namespace === 0 ? ua.DataType[dt.value] : String(dt);
            console.log(`attrs ${node} ${dtName} ${r[1].value.value} ${show(r[2].value.value)} ${r[3].value.value} ${r[4].value.value}`);
        } else if (op === "read") {
            const dv = await session.read({ nodeId: id(node), attributeId: ua.AttributeIds.Value });
            const ts = dv.sourceTimestamp ? dv.sourceTimestamp.getTime() : 0;
            console.log(`read ${node} ${dv.statusCode.name} ${show(dv.value.value)} ${ts}`);
        } else if (op === "write") {
            const st = await session.write(writeValue(p.slice(1)));
            console.log(`write ${node} ${st.name}`);
        } else if (op === "writes") {
            const parts = step.slice("writes:".length).split("|").map((w) => w.split(":"));
            const st = await session.write(parts.map(writeValue));
            parts.forEach((w, i) => console.log(`write ${w[0]} ${st[i].name}`));
        } else if (op === "wait") {
            const want = p[2], deadline = Date.now() + 1000 * Number(p[3]);
            let got = "";
            while (Date.now() < deadline) {
                const dv = await session.read({ nodeId: id(node), attributeId: ua.AttributeIds.Value });
                got = dv.statusCode.name;
                if (got === want) break;
                await new Promise((r) => setTimeout(r, 100));
            }
            console.log(`wait ${node} ${got}`);
        } else if (op === "kill") {
            process.kill(Number(p[1]), p[2]);
            console.log(`kill ${p[1]} ${p[2]}`);
        } else if (op === "waitval") {
            const want = p.slice(2, -1).join(":"), deadline = Date.now() + 1000 * Number(p[p.length - 1]);
            let dv;
            do {
                dv = await session.read({ nodeId: id(node), attributeId: ua.AttributeIds.Value });
                if (show(dv.value.value) === want) break;
                await new Promise((r) => setTimeout(r, 100));
            } while (Date.now() < deadline);
            console.log(`waitval ${node} ${dv.statusCode.name} ${show(dv.value.value)}`);
        } else if (op === "sub") {
            const want = Number(p[2]), seconds = Number(p[3]);
            const sub = await session.createSubscription2({ requestedPublishingInterval: 100, publishingEnabled: true,
                requestedLifetimeCount: 100, requestedMaxKeepAliveCount: 10 });
            const item = await sub.monitor({ nodeId: id(node), attributeId: ua.AttributeIds.Value },
                { samplingInterval: 100, queueSize: 10, discardOldest: true }, ua.TimestampsToReturn.Both);
            // one Publish response can carry several notifications of the item (a loaded machine, a
            // client late to ask): node-opcua emits them one after another before the promise's
            // continuation runs, so those after the N-th are ignored here, not counted
            let n = 0;
            await new Promise((resolve) => {
                const t = setTimeout(resolve, seconds * 1000);
                item.on("changed", (dv) => {
                    if (n >= want) return;
                    n++;
                    console.log(`sub ${node} ${dv.statusCode.name} ${show(dv.value.value)}`);
                    if (n >= want) { clearTimeout(t); resolve(); }
                });
            });
            console.log(`subdone ${node} ${n}`);
            await sub.terminate();
        } else {
            console.log("error unknown step " + step);
        }
    }
    await session.close();
    await client.disconnect();
    return 0;
}

main().then((rc) => process.exit(rc), (e) => { console.log("error " + e.message.split("\n")[0]); process.exit(1); });
