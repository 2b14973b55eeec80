/* SPDX-License-Identifier: MPL-2.0 */
/*
 * bench_gw - df1gw's end-to-end latency (bench/bench_gw.sh starts mosquitto,
 * df1sim and df1gw): a write through PREFIX/tag/Speed/set changes N7:0 in
 * df1sim; its result says the change is in the PLC; the message of the tag
 * Mirror (a Read tag on the same N7:0) then says df1gw read it and published
 * it. Reported: result -> Mirror (a change in the PLC to its MQTT message:
 * the wait for the next scan, the read, JSON, the broker) and set -> result
 * (a write's round trip). A benchmark reports numbers; it asserts nothing.
 *
 * Each write starts at a random point of the scan period (SCAN_MS), so the
 * wait for the next scan is spread as it is for a change the PLC makes.
 *
 * usage: bench_gw PORT PREFIX COUNT SCAN_MS
 */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mosquitto.h>

static double now_ms(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000.0 + ts.tv_nsec / 1e6;
}

struct run {
	char prefix[256];
	int want;               /* the value written this round */
	double t_set, t_result, t_mirror;
	int subscribed;
};

static void on_message(struct mosquitto *m, void *obj, const struct mosquitto_message *msg)
{
	struct run *r = obj;
	char topic[300], want[64];
	const char *p = msg->payload;

	(void)m;
	if (!p)
		return;
	snprintf(topic, sizeof topic, "%s/tag/Speed/result", r->prefix);
	if (strcmp(msg->topic, topic) == 0 && !r->t_result) {
		r->t_result = now_ms();
		return;
	}
	snprintf(topic, sizeof topic, "%s/tag/Mirror", r->prefix);
	snprintf(want, sizeof want, "{\"value\":%d,", r->want);
	if (strcmp(msg->topic, topic) == 0 && msg->payloadlen > (int)strlen(want) &&
	    strncmp(p, want, strlen(want)) == 0 && r->t_result && !r->t_mirror)
		r->t_mirror = now_ms();
}

static void on_subscribe(struct mosquitto *m, void *obj, int mid, int n, const int *q)
{
	(void)m, (void)mid, (void)n, (void)q;
	((struct run *)obj)->subscribed++;
}

static int cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

static void report(const char *what, double *v, int n)
{
	double sum = 0;

	qsort(v, (size_t)n, sizeof *v, cmp);
	for (int i = 0; i < n; i++)
		sum += v[i];
	printf("bench_gw: %-34s median %6.1f ms, mean %6.1f ms, p90 %6.1f ms, max %6.1f ms (%d writes)\n",
	       what, v[n / 2], sum / n, v[(n * 9) / 10], v[n - 1], n);
}

/* Run libmosquitto until cond or deadline; 0 if cond held. */
static int pump(struct mosquitto *m, struct run *r, int (*cond)(const struct run *), double deadline)
{
	while (!cond(r)) {
		if (now_ms() > deadline)
			return -1;
		if (mosquitto_loop(m, 10, 1) != MOSQ_ERR_SUCCESS)
			return -1;
	}
	return 0;
}

static int is_subscribed(const struct run *r) { return r->subscribed >= 2; }
static int never(const struct run *r) { (void)r; return 0; }
static int has_mirror(const struct run *r) { return r->t_mirror > 0; }

int main(int argc, char **argv)
{
	struct run r;
	struct mosquitto *m;
	int port, count, done = 0, scan_ms;
	double *change, *write;
	char topic[300], payload[64];

	if (argc != 5) {
		fprintf(stderr, "usage: bench_gw PORT PREFIX COUNT SCAN_MS\n");
		return 2;
	}
	scan_ms = atoi(argv[4]);
	srand((unsigned)time(NULL));
	port = atoi(argv[1]);
	count = atoi(argv[3]);
	memset(&r, 0, sizeof r);
	snprintf(r.prefix, sizeof r.prefix, "%s", argv[2]);
	change = calloc((size_t)count, sizeof *change);
	write = calloc((size_t)count, sizeof *write);
	mosquitto_lib_init();
	m = mosquitto_new(NULL, true, &r);
	if (!m || !change || !write)
		return 1;
	mosquitto_int_option(m, MOSQ_OPT_TCP_NODELAY, 1);
	mosquitto_message_callback_set(m, on_message);
	mosquitto_subscribe_callback_set(m, on_subscribe);
	if (mosquitto_connect(m, "127.0.0.1", port, 30) != MOSQ_ERR_SUCCESS) {
		fprintf(stderr, "bench_gw: cannot connect to the broker on port %d\n", port);
		return 1;
	}
	snprintf(topic, sizeof topic, "%s/tag/Speed/result", r.prefix);
	mosquitto_subscribe(m, NULL, topic, 1);
	snprintf(topic, sizeof topic, "%s/tag/Mirror", r.prefix);
	mosquitto_subscribe(m, NULL, topic, 1);
	if (pump(m, &r, is_subscribed, now_ms() + 5000) < 0)
		return 1;
	for (int i = 0; i < count; i++) {
		if (scan_ms > 0)
			pump(m, &r, never, now_ms() + rand() % scan_ms);
		r.want = 1000 + i;
		r.t_result = r.t_mirror = 0;
		snprintf(topic, sizeof topic, "%s/tag/Speed/set", r.prefix);
		snprintf(payload, sizeof payload, "{\"value\":%d,\"id\":\"bench-%d-%ld\"}", r.want, i, (long)time(NULL));
		r.t_set = now_ms();
		mosquitto_publish(m, NULL, topic, (int)strlen(payload), payload, 1, false);
		if (pump(m, &r, has_mirror, now_ms() + 10000) < 0) {
			fprintf(stderr, "bench_gw: write %d: no result or no change seen\n", i);
			break;
		}
		change[done] = r.t_mirror - r.t_result;
		write[done] = r.t_result - r.t_set;
		done++;
	}
	if (done) {
		report("change in the PLC -> MQTT message", change, done);
		report("write: .../set -> .../result", write, done);
	}
	mosquitto_destroy(m);
	mosquitto_lib_cleanup();
	return done == count ? 0 : 1;
}
