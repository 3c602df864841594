# Peer timings for benchmarks/bench_arma.py: R's exact-ML arima() on the five candidates and
# forecast::auto.arima over p <= 3, q <= 1, on the same standardised series.
#
# Usage: Rscript benchmarks/r_arima.R DATA.f64 N [auto]
#   DATA.f64: N little-endian float64 values (written by bench_arma.py).
# Prints one line per result: "fit <p> <q> <seconds> <loglik> <aic> <coef...>",
# "auto <seconds> <p> <q> <aic>", "total_arima <seconds>", "cpu_total_arima <seconds>" and
# "auto_cpu <seconds>".  Times are R's own system.time() elapsed seconds, the cpu lines its
# user + system seconds (R start-up and reading the data are not included).

args <- commandArgs(trailingOnly = TRUE)
path <- args[1]
n <- as.integer(args[2])
do_auto <- length(args) >= 3 && args[3] == "auto"
con <- file(path, "rb")
y <- readBin(con, "double", n = n, size = 8, endian = "little")
close(con)

orders <- list(c(1, 0), c(2, 0), c(3, 0), c(1, 1), c(2, 1))
total <- 0
cpu_total <- 0
for (o in orders) {
  fit <- NULL
  st <- system.time(fit <- arima(y, order = c(o[1], 0, o[2]), include.mean = FALSE,
                                 method = "ML"))
  t <- st[["elapsed"]]
  total <- total + t
  cpu_total <- cpu_total + st[["user.self"]] + st[["sys.self"]]
  cat("fit", o[1], o[2], format(t, digits = 6), format(fit$loglik, digits = 15),
      format(fit$aic, digits = 15), format(coef(fit), digits = 15), "\n")
}
cat("total_arima", format(total, digits = 6), "\n")
cat("cpu_total_arima", format(cpu_total, digits = 6), "\n")

if (do_auto) {
  suppressPackageStartupMessages(library(forecast))
  a <- NULL
  st <- system.time(a <- auto.arima(y, d = 0, max.p = 3, max.q = 1, stepwise = FALSE,
                                    allowmean = FALSE, approximation = FALSE))
  ord <- arimaorder(a)
  cat("auto", format(st[["elapsed"]], digits = 6), ord[1], ord[3], format(a$aic, digits = 15),
      "\n")
  cat("auto_cpu", format(st[["user.self"]] + st[["sys.self"]], digits = 6), "\n")
}
